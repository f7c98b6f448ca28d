! code_saturne's ALE boundary conditions (usalcl), moving the mesh with meshmove.
!
! On the first call the meshmove mesh is built from code_saturne's own face-based arrays
! (interior faces ipnfac/nodfac with their cells ifacel, boundary faces ipnfbr/nodfbr with their
! cell ifabor, each boundary face's zone from getfbr) and the solver is kept for the run
! (meshmove_cylinder, cs_user_modules.f90). Every time step meshmove moves the mesh to the
! cylinder's position and the displacement of every vertex is imposed (impale = 1, disale the
! total displacement from xyzno0), so code_saturne's own mesh solve decides nothing.
!
! Under MPI (code_saturne on several ranks, irangp >= 0) each rank gives meshmove's distributed
! mesh its own cells by their faces, a face to a halo cell marked as shared with another rank,
! with the global number of each of its vertices (meshmove_ranks.c), and moves with the
! distributed solver (module meshmove_cylinder_ranks below): every rank imposes the displacement
! of all its vertices, those it shares with other ranks getting the same values on each. The
! distributed calls need meshmove built with MPI and -DMESHMOVE_MPI in the Fortran flags
! (DATA/cs_user_scripts.py; code_saturne runs every user Fortran file through the C
! preprocessor); without it a run on several ranks stops with a message.
!
! With the environment variable CS_MESH_MOVER=code_saturne the same case runs code_saturne's
! own ALE mesh solve instead (for the comparison in docs/RESULTS.md): only the cylinder's
! vertices are imposed, the channel's faces are fixed and the symmetry planes sliding.
!
! A serial run writes the face mesh to meshmove_faces.bin on the first call, for the check
! program (check_steps.f90).

#ifdef MESHMOVE_MPI
!> The distributed solver of an MPI run, kept for the run: made from the rank's face mesh, it
!> moves the rank's vertices for advance_meshmove (meshmove_cylinder) each time step.
module meshmove_cylinder_ranks
  use, intrinsic :: iso_c_binding
  use meshmove, only: mm_last_error
  use meshmove_c
  use meshmove_mpi
  use meshmove_cylinder
  implicit none
  private

  type(c_ptr), save :: solver = c_null_ptr

  public :: start_meshmove_ranks, move_ranks

contains

  !> The distributed solver on code_saturne's communicator `comm` (Fortran handle) from this
  !> rank's own cells `m` (a face to another rank's cell has that cell 0 and patch -1) and the
  !> global number of each of its vertices; the conditions of the serial solver
  !> (meshmove_cylinder's `conditions`). Collective. stat is meshmove's status, errmsg its
  !> message.
  subroutine start_meshmove_ranks(comm, m, gnum, stat, errmsg)
    integer(c_int32_t), intent(in) :: comm
    type(face_mesh), intent(in) :: m
    integer(c_int64_t), intent(in) :: gnum(:)
    integer(c_int32_t), intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    type(c_ptr) :: mesh, bcs, options
    integer(c_int32_t) :: freed
    integer :: i
    errmsg = ""
    bcs = c_null_ptr
    options = c_null_ptr
    ! The C call's CSR offsets start at 0 whatever the index base; the face mesh's at 1.
    stat = meshmove_dist_mesh_create_from_faces_f(comm, 3, size(m%coords, 2), m%coords, size(m%owner), &
      m%offsets - 1, size(m%vertices), m%vertices, m%owner, m%neighbour, m%patch, m%num_cells, c_null_ptr, 1, &
      gnum, mesh)
    if (stat /= MESHMOVE_STATUS_OK) then
      errmsg = mm_last_error()
      return
    end if
    stat = meshmove_bcs_create(bcs)
    do i = 1, size(conditions, 2)
      if (stat /= MESHMOVE_STATUS_OK) exit
      if (conditions(2, i) == 0) then
        stat = meshmove_bcs_set_kinds(bcs, conditions(1, i), conditions(3, i))
      else
        stat = meshmove_bcs_set_kind(bcs, conditions(1, i), conditions(2, i) - 1, conditions(3, i))
      end if
    end do
    if (stat == MESHMOVE_STATUS_OK) stat = meshmove_options_create(options)
    if (stat == MESHMOVE_STATUS_OK) stat = meshmove_options_set_tol(options, ranks_tol)
    if (stat == MESHMOVE_STATUS_OK) stat = meshmove_dist_solver_create(mesh, bcs, options, solver)
    if (stat /= MESHMOVE_STATUS_OK) errmsg = mm_last_error()
    ! The solver holds what it needs of these: freeing them cannot fail on valid handles.
    freed = meshmove_options_free(options)
    freed = meshmove_bcs_free(bcs)
    freed = meshmove_dist_mesh_free(mesh)
    if (stat == MESHMOVE_STATUS_OK) call begin_motion(m%coords)
  end subroutine

  !> One step of the distributed solver (collective): the cylinder translated rigidly, every
  !> other boundary at rest, the rank's vertices moved in xyz (body_move of meshmove_cylinder).
  subroutine move_ranks(translation, centre, xyz, stat, errmsg)
    real(c_double), intent(in) :: translation(3), centre(3)
    real(c_double), intent(inout) :: xyz(:, :)
    integer(c_int32_t), intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(c_double), allocatable :: bd(:, :)
    type(meshmove_dist_report) :: report
    errmsg = ""
    allocate (bd(3, size(xyz, 2)))
    bd = 0
    stat = meshmove_dist_solver_set_rigid_motion(solver, body, translation, [0.0_c_double, 0.0_c_double, &
      0.0_c_double], centre)
    if (stat == MESHMOVE_STATUS_OK) stat = meshmove_dist_solver_move(solver, bd, size(bd), xyz, size(xyz), report)
    if (stat /= MESHMOVE_STATUS_OK) errmsg = mm_last_error()
  end subroutine
end module meshmove_cylinder_ranks
#endif

subroutine usalcl(itrale, nvar, nscal, icodcl, itypfb, ialtyb, impale, dt, rcodcl, xyzno0, disale)
  use, intrinsic :: iso_c_binding, only: c_int32_t
#ifdef MESHMOVE_MPI
  use, intrinsic :: iso_c_binding, only: c_int64_t
#endif
  use paramx, only: ibfixe, igliss
  use optcal, only: ntcabs
  use entsor, only: nfecra
  use parall, only: irangp
  use mesh, only: ncel, ncelet, nfac, nfabor, nnod, ifacel, ifabor, ipnfac, nodfac, ipnfbr, nodfbr
  use meshmove_cylinder
#ifdef MESHMOVE_MPI
  use saturne_ranks
  use meshmove_cylinder_ranks
#endif
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
#ifdef MESHMOVE_MPI
  integer(c_int64_t), allocatable :: gnum(:)
#endif
  integer :: nlelt, i, ifac, ii, inod
  integer(c_int32_t) :: stat
  character(len=:), allocatable :: errmsg
  double precision :: dy

  if (first) then
    call get_environment_variable("CS_MESH_MOVER", mover)
    with_meshmove = mover /= "code_saturne"
    call read_motion()
    call faces_of_saturne(m)
    if (irangp < 0) call write_face_mesh(m, "meshmove_faces.bin")
    if (with_meshmove .and. irangp >= 0) then
      ! Several ranks: the distributed solver on code_saturne's communicator, collectively.
#ifdef MESHMOVE_MPI
      allocate (gnum(nnod))
      call saturne_global_vertices(int(nnod, c_int32_t), gnum)
      call start_meshmove_ranks(saturne_comm(), m, gnum, stat, errmsg)
      call stop_on_failure("meshmove's distributed solver")
#else
      write (nfecra, "(a)") "usalcl: a run on several ranks needs meshmove built with MPI and this file " // &
        "compiled with -DMESHMOVE_MPI (MESHMOVE_FFLAGS)"
      call csexit(1)
#endif
    else if (with_meshmove) then
      ! Ghost cells in a serial run (periodicity) need meshmove's distributed solver too.
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
#ifdef MESHMOVE_MPI
    if (irangp >= 0) then
      call advance_meshmove(ntcabs, stat, errmsg, move_ranks)
    else
      call advance_meshmove(ntcabs, stat, errmsg)
    end if
#else
    call advance_meshmove(ntcabs, stat, errmsg)
#endif
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
  !> (their neighbour 0 and their zone as patch), the original coordinates xyzno0. The rank's
  !> own cells alone: a halo cell (beyond ncel; none in a serial run) is another rank's, and
  !> its side of a face becomes 0 (below meshmove's index base 1: shared with another rank).
  !> code_saturne's module mesh gives the 1-based connectivity as elemental functions
  !> (ipnfac(f), nodfac(i), ifacel(k, f), ...).
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
      fm%owner(f) = merge(ifacel(1, f), 0, ifacel(1, f) <= ncel)
      fm%neighbour(f) = merge(ifacel(2, f), 0, ifacel(2, f) <= ncel)
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
