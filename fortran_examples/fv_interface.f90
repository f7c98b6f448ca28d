! A legacy-style two-region code (paper Fig. 11): regions 0 (y < 0) and 1 (y > 0) share the
! interface y = 0, which the "flow solver" deforms to y = 0.25 cos(2 pi x) over 15 time steps.
! Each step the code fills a boundary-displacement array and calls the mover once, in place:
!     call solver%move(bd, xy)          ! was: call spring_move(xy, bd)
! Interface CLAMPED on each side (variant A, SEPARATE), bottom and top FIXED, sides sliding in y.
! The code owns its mesh: a 16 x 32 grid of triangles on [0,1]x[-1,1] (box_grid.f90), the row
! y = 0 tagged as the interface, region 1 above it.
! Checks each step: no inverted cell, each region's area conserved (the interface is the only
! moving boundary and the sides slide), the interface where it was put.
! Usage: fv_interface_f OUT.vtu
program fv_interface
  use, intrinsic :: iso_c_binding
  use meshmove
  use box_grid, only: make_box_grid
  implicit none (type, external)
  integer, parameter :: nsteps = 15, nx = 16, ny = 32
  integer(c_int32_t), parameter :: bottom = 1, right = 2, interface = 3, left = 4, top = 5
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  type(meshmove_report) :: rep
  type(meshmove_quality) :: q
  real(c_double), allocatable :: xy(:, :), bd(:, :)
  integer(c_int32_t), allocatable :: cells(:, :), region(:), iface(:), bedges(:, :), bpatches(:), edges(:, :), &
    patches(:)
  real(c_double), parameter :: pi = acos(-1.0_c_double), amp = 0.25_c_double
  real(c_double) :: a0(0:1), a(0:1), minratio, err
  character(len=256) :: out
  integer :: n, i, nb

  out = "fv_interface_f.vtu"
  if (command_argument_count() > 0) call get_command_argument(1, out)

  ! The grid, its interface row (vertices ny/2 (nx + 1) + 1 ...) as tagged interior edges after
  ! the boundary ones, and the regions: the lower half of the cells 0, the upper half 1.
  call make_box_grid(nx, ny, [0.0_c_double, 1.0_c_double, -1.0_c_double, 1.0_c_double], [bottom, right, top, left], &
    xy, cells, bedges, bpatches)
  nb = size(bpatches)
  allocate (iface(nx + 1), edges(2, nb + nx), patches(nb + nx), region(size(cells, 2)))
  do i = 1, nx + 1
    iface(i) = ny / 2 * (nx + 1) + i
  end do
  edges(:, 1:nb) = bedges
  patches(1:nb) = bpatches
  do i = 1, nx
    edges(:, nb + i) = [iface(i), iface(i + 1)]
    patches(nb + i) = interface
  end do
  region(1:size(region) / 2) = 0
  region(size(region) / 2 + 1:) = 1
  call mesh%create_triangles(xy, cells, edges, patches, region)
  call bcs%create()
  call bcs%set_kinds(bottom, MESHMOVE_KIND_FIXED)
  call bcs%set_kinds(top, MESHMOVE_KIND_FIXED)
  call bcs%set_kinds(interface, MESHMOVE_KIND_CLAMPED)
  call bcs%set_interface(interface, MESHMOVE_INTERFACE_SEPARATE)
  call bcs%set_kind(left, 2, MESHMOVE_KIND_FREE)
  call bcs%set_kind(right, 2, MESHMOVE_KIND_FREE)
  call solver%create(mesh, bcs)
  call areas(a0)
  print '(a, i0, a, i0, a, 2f10.6)', "fv_interface (Fortran): ", size(xy, 2), " vertices, ", size(cells, 2), &
    " cells, region areas", a0

  allocate (bd(2, size(xy, 2)))
  minratio = huge(1.0_c_double)
  do n = 1, nsteps
    bd = 0
    do i = 1, size(iface)
      bd(2, iface(i)) = amp * cos(2.0_c_double * pi * xy(1, iface(i))) / 15.0_c_double
    end do
    call solver%move(bd, xy, rep, q)
    call areas(a)
    minratio = min(minratio, q%min_volume_ratio)
    print '(a, i2, a, i3, a, i0, a, f7.4, a, 2es10.2)', "  step ", n, ": ", rep%cycles, " cycles, inverted ", &
      q%inverted, ", min area ratio ", q%min_volume_ratio, ", region area change ", a - a0
    if (q%inverted /= 0 .or. rep%converged /= 1) error stop "inverted cell or no convergence"
  end do
  ! Region areas: the interface moved by amp cos(2 pi x), whose integral over [0,1] is 0 up to
  ! the piecewise-linear quadrature, so each region keeps its area.
  if (any(abs(a - a0) > 1e-12_c_double)) error stop "region area not conserved"
  err = 0
  do i = 1, size(iface)
    err = max(err, abs(xy(2, iface(i)) - amp * cos(2.0_c_double * pi * xy(1, iface(i)))))
  end do
  print '(a, es10.2, a, f7.4)', "  interface error ", err, ", min area ratio over all steps ", minratio
  if (err > 1e-12_c_double) error stop "interface not where it was put"
  call solver%write_vtu(trim(out))
  call solver%free()
  call bcs%free()
  call mesh%free()
contains
  subroutine areas(r)
    real(c_double), intent(out) :: r(0:1)
    integer :: c
    real(c_double) :: p(2), s(2), t(2)
    r = 0
    do c = 1, size(cells, 2)
      p = xy(:, cells(1, c))
      s = xy(:, cells(2, c)) - p
      t = xy(:, cells(3, c)) - p
      r(region(c)) = r(region(c)) + 0.5_c_double * (s(1) * t(2) - s(2) * t(1))
    end do
  end subroutine
end program
