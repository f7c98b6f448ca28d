! The paper's first case through the Fortran module: the box [0,1]x[-1,0], top raised to
! y = 0.25 cos(2 pi x), bottom FIXED, top CLAMPED, sides x-periodic (x CLAMPED, y FREE).
! Usage: free_surface_f OUT.vtu   (ctest compares OUT.vtu with the Rust library's result)
program free_surface
  use, intrinsic :: iso_c_binding
  use meshmove
  implicit none (type, external)
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  type(meshmove_report) :: rep
  real(c_double), allocatable :: xy(:, :), d(:, :)
  integer(c_int32_t), allocatable :: top(:)
  character(len=256) :: out
  real(c_double), parameter :: pi = acos(-1.0_c_double)
  integer :: i, stat

  out = "free_surface_f.vtu"
  if (command_argument_count() > 0) call get_command_argument(1, out)

  call mesh%create_case("free_surface", 1.0_c_double / 32)
  call bcs%create()
  call bcs%set_kinds(MESHMOVE_FS_BOTTOM, MESHMOVE_KIND_FIXED)
  call bcs%set_kinds(MESHMOVE_FS_TOP, MESHMOVE_KIND_CLAMPED)
  call bcs%set_kind(MESHMOVE_FS_LEFT, 1, MESHMOVE_KIND_CLAMPED)   ! component 1 = x
  call bcs%set_kind(MESHMOVE_FS_LEFT, 2, MESHMOVE_KIND_FREE)      ! component 2 = y
  call bcs%set_kind(MESHMOVE_FS_RIGHT, 1, MESHMOVE_KIND_CLAMPED)
  call bcs%set_kind(MESHMOVE_FS_RIGHT, 2, MESHMOVE_KIND_FREE)
  call bcs%link_periodic(MESHMOVE_FS_LEFT, MESHMOVE_FS_RIGHT, 1.0_c_double, 0.0_c_double, 1e-9_c_double)
  call solver%create(mesh, bcs)

  ! A bad call with `stat` present returns the status instead of stopping.
  call bcs%set_kinds(7, 99, stat=stat)
  if (stat /= MESHMOVE_STATUS_INVALID_ARGUMENT) error stop "expected INVALID_ARGUMENT for kind 99"
  print '(a, a)', "expected failure: ", mm_last_error()

  call mesh%coords(xy)
  call mesh%patch_vertices(MESHMOVE_FS_TOP, top)   ! 1-based
  allocate (d(2, size(xy, 2)), source=0.0_c_double)
  do i = 1, size(top)
    d(2, top(i)) = 0.25_c_double * cos(2.0_c_double * pi * xy(1, top(i)))
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
