! code_saturne's ALE boundary conditions (usalcl), moving the mesh with meshmove.
!
! On the first call the meshmove mesh is built from code_saturne's own face-based arrays
! (interior faces ipnfac/nodfac with their cells ifacel, boundary faces ipnfbr/nodfbr with their
! cell ifabor, each boundary face's zone from getfbr) and the solver is kept for the run
! (meshmove_cylinder, cs_user_modules.f90). Every time step meshmove moves the mesh to the
! cylinder's position and the displacement of every vertex is imposed (impale = 1, disale the
! total displacement from xyzno0), so code_saturne's own mesh solve decides nothing.
!
! With the environment variable CS_MESH_MOVER=code_saturne the same case runs code_saturne's
! own ALE mesh solve instead (for the comparison in docs/RESULTS.md): only the cylinder's
! vertices are imposed, the channel's faces are fixed and the symmetry planes sliding.
!
! Either way the face mesh is written to meshmove_faces.bin on the first call, for the check
! program (check_steps.f90).
subroutine usalcl(itrale, nvar, nscal, icodcl, itypfb, ialtyb, impale, dt, rcodcl, xyzno0, disale)
  use, intrinsic :: iso_c_binding, only: c_int32_t
  use paramx, only: ibfixe, igliss
  use optcal, only: ntcabs
  use entsor, only: nfecra
  use mesh, only: ncel, ncelet, nfac, nfabor, nnod, ifacel, ifabor, ipnfac, nodfac, ipnfbr, nodfbr
  use meshmove_cylinder
  implicit none

  integer itrale
  integer nvar, nscal
  integer icodcl(nfabor, nvar)
  integer itypfb(nfabor), ialtyb(nfabor)
  integer impale(nnod)
  double precision dt(ncelet)
  double precision rcodcl(nfabor, nvar, 3)
  double precision disale(3, nnod), xyzno0(3, nnod)

  logical, save :: first = .true., with_meshmove = .true.
  type(face_mesh) :: m
  character(len=32) :: mover
  integer, allocatable :: lstelt(:)
  integer :: nlelt, i, ifac, ii, inod
  integer(c_int32_t) :: stat
  character(len=:), allocatable :: errmsg
  double precision :: dy

  if (first) then
    call get_environment_variable("CS_MESH_MOVER", mover)
    with_meshmove = mover /= "code_saturne"
    call read_motion()
    call faces_of_saturne(m)
    call write_face_mesh(m, "meshmove_faces.bin")
    if (with_meshmove) then
      ! Ghost cells (MPI ranks, periodicity) need meshmove's distributed solver, not this one.
      if (ncelet /= ncel) then
        write (nfecra, "(a)") "usalcl: meshmove moves a serial mesh without periodicity here (ncelet /= ncel)"
        call csexit(1)
      end if
      call start_meshmove(m, stat, errmsg)
      call stop_on_failure("the meshmove solver")
    end if
    first = .false.
  end if

  if (with_meshmove) then
    call advance_meshmove(ntcabs, stat, errmsg)
    call stop_on_failure("meshmove's step")
    do inod = 1, nnod
      disale(:, inod) = moved(:, inod) - xyzno0(:, inod)
      impale(inod) = 1
    end do
  else
    ! code_saturne's own solve: the cylinder (zone 4) imposed, the inlet, outlet and walls (1, 2,
    ! 3) fixed, the symmetry planes (5) sliding.
    allocate (lstelt(nfabor))
    dy = body_offset(ntcabs)
    call getfbr("4", nlelt, lstelt)
    do i = 1, nlelt
      ifac = lstelt(i)
      do ii = ipnfbr(ifac), ipnfbr(ifac + 1) - 1
        inod = nodfbr(ii)
        disale(:, inod) = [0.d0, dy, 0.d0]
        impale(inod) = 1
      end do
    end do
    call getfbr("1 or 2 or 3", nlelt, lstelt)
    ialtyb(lstelt(1:nlelt)) = ibfixe
    call getfbr("5", nlelt, lstelt)
    ialtyb(lstelt(1:nlelt)) = igliss
    deallocate (lstelt)
  end if

contains

  !> A failed meshmove call stops the run with meshmove's message in code_saturne's log.
  subroutine stop_on_failure(what)
    character(*), intent(in) :: what
    if (stat == 0) return
    write (nfecra, "(a, a, i0, a, a)") what, " failed (meshmove status ", stat, "): ", errmsg
    call csexit(1)
  end subroutine

  !> code_saturne's mesh as meshmove's face mesh: the interior faces, then the boundary faces
  !> (their neighbour 0 and their zone as patch), the original coordinates xyzno0. Serial:
  !> every cell a face names is a local cell (ncel = ncelet). code_saturne's module mesh gives
  !> the 1-based connectivity as elemental functions (ipnfac(f), nodfac(i), ifacel(k, f), ...).
  subroutine faces_of_saturne(fm)
    type(face_mesh), intent(out) :: fm
    integer :: f, z, n, nb
    character(len=8) :: zone
    n = ipnfac(nfac + 1) - 1
    nb = ipnfbr(nfabor + 1) - 1
    fm%coords = xyzno0
    fm%num_cells = ncel
    allocate (fm%offsets(nfac + nfabor + 1), fm%vertices(n + nb), fm%owner(nfac + nfabor), &
      fm%neighbour(nfac + nfabor), fm%patch(nfac + nfabor))
    do f = 1, nfac
      fm%offsets(f) = ipnfac(f)
      fm%owner(f) = ifacel(1, f)
      fm%neighbour(f) = ifacel(2, f)
    end do
    do f = 1, nfabor + 1
      fm%offsets(nfac + f) = ipnfbr(f) + n
    end do
    do f = 1, nfabor
      fm%owner(nfac + f) = ifabor(f)
      fm%neighbour(nfac + f) = 0
    end do
    do f = 1, n
      fm%vertices(f) = nodfac(f)
    end do
    do f = 1, nb
      fm%vertices(n + f) = nodfbr(f)
    end do
    fm%patch = -1
    allocate (lstelt(nfabor))
    do z = 1, num_zones
      write (zone, "(i0)") z
      call getfbr(trim(zone), nlelt, lstelt)
      do f = 1, nlelt
        fm%patch(nfac + lstelt(f)) = z
      end do
    end do
    deallocate (lstelt)
  end subroutine
end subroutine usalcl
