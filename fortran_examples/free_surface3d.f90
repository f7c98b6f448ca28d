! The free surface in 3D through the Fortran module: the box [0,1]x[0,1]x[-1,0] of 8 x 8 x 8
! hexahedra (box_grid.f90's make_hex_grid, given to meshmove through the generic call with
! quadrilateral faces), its top raised to z = 0.15 cos(2 pi x) cos(2 pi y) in 5 time steps, one
! call per step:
!     call solver%move(bd, xyz)         ! was: call spring_move(xyz, bd)
! Bottom FIXED, top CLAMPED, the sides sliding: the normal component CLAMPED, the others FREE.
! Checks each step: no inverted cell, the volume stays 1 (the top's displacement has zero mean on
! the grid and the sides stay in their planes); at the end the top is where it was put.
! Usage: free_surface3d_f OUT.vtu   (ctest compares OUT.vtu with the Rust library's result)
program free_surface3d
  use, intrinsic :: iso_c_binding
  use meshmove
  use box_grid, only: make_hex_grid
  implicit none (type, external)
  integer, parameter :: n = 8, nsteps = 5
  integer(c_int32_t), parameter :: bottom = 1, top = 2, xside = 3, yside = 4
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  type(meshmove_report) :: rep
  type(meshmove_quality) :: q
  real(c_double), allocatable :: xyz(:, :), bd(:, :)
  integer(c_int32_t), allocatable :: cells(:, :), faces(:, :), patches(:), tops(:)
  real(c_double), parameter :: pi = acos(-1.0_c_double), amp = 0.15_c_double
  real(c_double) :: vol, worst, err
  character(len=256) :: out
  integer :: s, i, v

  out = "free_surface3d_f.vtu"
  if (command_argument_count() > 0) call get_command_argument(1, out)

  ! The faces in the hexahedron's order z-, z+, y-, x+, y+, x- get the patches below.
  call make_hex_grid(n, [0.0_c_double, 0.0_c_double, -1.0_c_double], [1.0_c_double, 1.0_c_double, 0.0_c_double], &
    [bottom, top, yside, xside, yside, xside], xyz, cells, faces, patches)
  call mesh%create(xyz, spread(MESHMOVE_CELL_TYPE_HEXAHEDRON, 1, size(cells, 2)), reshape(cells, [size(cells)]), &
    face_connectivity=reshape(faces, [size(faces)]), face_patch=patches, &
    face_offsets=[(int(4 * i + 1, c_int32_t), i = 0, size(patches))])
  if (mesh%dim() /= 3) error stop "not a 3D mesh"
  call mesh%patch_vertices(top, tops)
  call bcs%create()
  call bcs%set_kinds(bottom, MESHMOVE_KIND_FIXED)
  call bcs%set_kinds(top, MESHMOVE_KIND_CLAMPED)
  call bcs%set_kinds(xside, MESHMOVE_KIND_FREE)
  call bcs%set_kind(xside, 1, MESHMOVE_KIND_CLAMPED)  ! component 1 = x, the normal of the x sides
  call bcs%set_kinds(yside, MESHMOVE_KIND_FREE)
  call bcs%set_kind(yside, 2, MESHMOVE_KIND_CLAMPED)  ! component 2 = y
  call solver%create(mesh, bcs)
  print '(a, i0, a, i0, a, i0, a, f12.9)', "free_surface3d (Fortran): ", size(xyz, 2), " vertices, ", &
    size(cells, 2), " hexahedra, ", size(tops), " top vertices, volume ", volume()

  allocate (bd(3, size(xyz, 2)))
  worst = 0
  do s = 1, nsteps
    bd = 0
    do i = 1, size(tops)
      v = tops(i)
      bd(3, v) = amp * cos(2.0_c_double * pi * xyz(1, v)) * cos(2.0_c_double * pi * xyz(2, v)) / nsteps
    end do
    call solver%move(bd, xyz, rep, q)
    vol = volume()
    worst = max(worst, abs(vol - 1.0_c_double))
    print '(a, i2, a, i3, a, i0, a, f7.4, a, es10.2)', "  step ", s, ": ", rep%cycles, " cycles, inverted ", &
      q%inverted, ", min volume ratio ", q%min_volume_ratio, ", volume error ", vol - 1.0_c_double
    if (q%inverted /= 0 .or. rep%converged /= 1) error stop "inverted cell or no convergence"
  end do
  err = 0
  do i = 1, size(tops)
    v = tops(i)
    err = max(err, abs(xyz(3, v) - amp * cos(2.0_c_double * pi * xyz(1, v)) * cos(2.0_c_double * pi * xyz(2, v))))
  end do
  print '(a, es10.2, a, es10.2)', "  worst volume error ", worst, ", top error ", err
  if (worst > 1e-12_c_double) error stop "volume not conserved"
  if (err > 1e-12_c_double) error stop "top not where it was put"
  call solver%write_vtu(trim(out))
  call solver%free()
  call bcs%free()
  call mesh%free()
contains
  ! The mesh's volume: each hexahedron's faces split into four triangles about their centroid
  ! (the same split from both sides of a face), summed as tetrahedra from the cell's first corner.
  real(c_double) function volume()
    integer, parameter :: hex_face(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, 2, 3, 7, 6, 3, 4, 8, 7, &
      4, 1, 5, 8], [4, 6])
    integer :: c, f, l
    real(c_double) :: o(3), a(3), b(3), m(3)
    volume = 0
    do c = 1, size(cells, 2)
      o = xyz(:, cells(1, c))
      do f = 1, 6
        m = 0.25_c_double * sum(xyz(:, cells(hex_face(:, f), c)), dim=2) - o
        do l = 1, 4
          a = xyz(:, cells(hex_face(l, f), c)) - o
          b = xyz(:, cells(hex_face(mod(l, 4) + 1, f), c)) - o
          volume = volume + (a(1) * (b(2) * m(3) - b(3) * m(2)) + a(2) * (b(3) * m(1) - b(1) * m(3)) + &
            a(3) * (b(1) * m(2) - b(2) * m(1))) / 6.0_c_double
        end do
      end do
    end do
  end function
end program
