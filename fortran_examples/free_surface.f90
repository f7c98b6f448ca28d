! The paper's first case through the Fortran module: the box [0,1]x[-1,0], top raised to
! y = 0.25 cos(2 pi x), bottom FIXED, top CLAMPED, sides x-periodic (x CLAMPED, y FREE).
! The mesh is the program's own: a 32 x 32 grid of triangles (box_grid.f90), given to meshmove as
! arrays through the generic call. Usage: free_surface_f OUT.vtu   (ctest compares OUT.vtu with
! the Rust library's result)
program free_surface
  use, intrinsic :: iso_c_binding
  use meshmove
  use box_grid, only: make_box_grid
  implicit none (type, external)
  integer(c_int32_t), parameter :: bottom = 1, right = 2, top = 3, left = 4
  integer, parameter :: n = 32
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_options) :: options
  type(mm_solver) :: solver
  type(meshmove_report) :: rep
  real(c_double), allocatable :: xy(:, :), d(:, :)
  integer(c_int32_t), allocatable :: cells(:, :), edges(:, :), patches(:)
  character(len=256) :: out
  real(c_double), parameter :: pi = acos(-1.0_c_double)
  integer(c_int32_t) :: major, minor, patch
  integer :: i, stat, v

  out = "free_surface_f.vtu"
  if (command_argument_count() > 0) call get_command_argument(1, out)
  call mm_version(major, minor, patch)
  if (major /= MESHMOVE_VERSION_MAJOR .or. minor /= MESHMOVE_VERSION_MINOR) error stop "library version differs"

  call make_box_grid(n, n, [0.0_c_double, 1.0_c_double, -1.0_c_double, 0.0_c_double], [bottom, right, top, left], &
    xy, cells, edges, patches)
  call mesh%create(xy, spread(MESHMOVE_CELL_TYPE_TRIANGLE, 1, size(cells, 2)), reshape(cells, [size(cells)]), &
    face_connectivity=reshape(edges, [size(edges)]), face_patch=patches)
  call bcs%create()
  call bcs%set_kinds(bottom, MESHMOVE_KIND_FIXED)
  call bcs%set_kinds(top, MESHMOVE_KIND_CLAMPED)
  call bcs%set_kind(left, 1, MESHMOVE_KIND_CLAMPED)   ! component 1 = x
  call bcs%set_kind(left, 2, MESHMOVE_KIND_FREE)      ! component 2 = y
  call bcs%set_kind(right, 1, MESHMOVE_KIND_CLAMPED)
  call bcs%set_kind(right, 2, MESHMOVE_KIND_FREE)
  call bcs%link_periodic(left, right, [1.0_c_double, 0.0_c_double], 1e-9_c_double)
  call options%create()                               ! the defaults
  call solver%create(mesh, bcs, options)
  call options%free()                                 ! the solver keeps its own copy

  ! A bad call with `stat` present returns the status instead of stopping.
  call bcs%set_kinds(7, 99, stat=stat)
  if (stat /= MESHMOVE_STATUS_INVALID_ARGUMENT) error stop "expected INVALID_ARGUMENT for kind 99"
  print '(a, a)', "expected failure: ", mm_last_error()

  ! The top row of the grid rises to 0.25 cos(2 pi x).
  allocate (d(2, size(xy, 2)), source=0.0_c_double)
  do i = 0, n
    v = n * (n + 1) + i + 1
    d(2, v) = 0.25_c_double * cos(2.0_c_double * pi * xy(1, v))
  end do
  call solver%solve(d, rep)
  print '(a, i0, a, es10.3, a, l1)', "free_surface (Fortran): ", rep%cycles, " cycles, rel residual ", &
    rep%rel_residual, ", converged ", rep%converged == 1
  call solver%write_vtu(trim(out), d)

  call solver%free()
  call bcs%free()
  call mesh%free()
  if (rep%converged /= 1) error stop "not converged"
end program
