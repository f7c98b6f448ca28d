! A host moving its mesh in several calls reads the totals since the initial mesh: the top of the
! unit square (8 x 8 cells in triangles) raised by a sine bump of 0.04 in four solver%move calls of
! a quarter each, then solver%displacement (the last increment), solver%get_total_displacement
! (all four) and solver%total_quality (against the initial mesh). Every integer has an explicit
! kind, so the test also compiles with -fdefault-integer-8 against the module built without it
! (ctest builds it both ways).
program totals
  use, intrinsic :: iso_c_binding
  use meshmove
  implicit none (type, external)
  integer(c_int32_t), parameter :: n = 8, one = 1, two = 2, nv = (n + one)**2
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  type(meshmove_quality) :: q, qt
  real(c_double) :: xy(2, nv), x0(2, nv), inc(2, nv)
  real(c_double), allocatable :: d(:, :), total(:, :)
  integer(c_int32_t) :: cells(3, 2 * n * n), tagged(2, n), patches(n), i, j, a, c, k, stat
  real(c_double), parameter :: pi = 3.14159265358979323846d0

  c = 0
  do j = 0_c_int32_t, n
    do i = 0_c_int32_t, n
      xy(:, j * (n + one) + i + one) = [real(i, c_double) / n, real(j, c_double) / n]
    end do
  end do
  do j = 0_c_int32_t, n - 1
    do i = 0_c_int32_t, n - 1
      a = j * (n + one) + i + one
      cells(:, c + one) = [a, a + one, a + n + two]
      cells(:, c + two) = [a, a + n + two, a + n + one]
      c = c + two
    end do
  end do
  do i = 1_c_int32_t, n
    tagged(:, i) = [n * (n + one) + i, n * (n + one) + i + one]
  end do
  patches = 2
  call mesh%create_triangles(xy, cells, tagged, patches, stat=stat)
  call ok(stat, "create_triangles")
  call bcs%create(stat=stat)
  call ok(stat, "bcs")
  call solver%create(mesh, bcs, stat=stat)
  call ok(stat, "solver")
  x0 = xy
  inc = 0
  do i = 0_c_int32_t, n
    inc(2, n * (n + one) + i + one) = 0.01d0 * sin(pi * i / n)
  end do
  do k = 1_c_int32_t, 4
    call solver%move(inc, xy, quality=q, stat=stat)
    call ok(stat, "move")
  end do
  call solver%displacement(d, stat=stat)
  call ok(stat, "displacement")
  call solver%get_total_displacement(total, stat=stat)
  call ok(stat, "get_total_displacement")
  call solver%total_quality(qt, stat=stat)
  call ok(stat, "total_quality")
  k = n * (n + one) + n / two + one
  if (any(total /= xy - x0)) error stop "the total displacement is not the positions minus the initial ones"
  if (abs(total(2, k) - 0.04d0) > 1d-15) error stop "the total at the top's middle is not 0.04"
  if (abs(d(2, k) - 0.01d0) > 1d-15) error stop "the last increment at the top's middle is not 0.01"
  if (.not. (qt%max_volume_ratio - 1 > 3 * (q%max_volume_ratio - 1))) error stop "total quality"
  ! Triangles: no negative area, and the corner Jacobian ratio is the area ratio.
  if (qt%negative_volume_cells /= 0 .or. abs(qt%min_corner_jacobian_ratio - qt%min_volume_ratio) > 1d-12) &
    error stop "the total quality's negative volumes or corner Jacobian ratio"
  call solver%write_vtu("fortran_totals.vtu", stat=stat)
  call ok(stat, "write_vtu")
  print '(a, f6.3, a, f6.3, a, f7.4, a, f7.4)', "totals: top ", total(2, k), " (last move ", d(2, k), &
    "), max area ratio ", qt%max_volume_ratio, " in all, last move ", q%max_volume_ratio
  call solver%free()
  call bcs%free()
  call mesh%free()
contains
  subroutine ok(stat, what)
    integer(c_int32_t), intent(in) :: stat
    character(*), intent(in) :: what
    if (stat /= MESHMOVE_STATUS_OK) then
      print '(a, a, a)', what, ": ", mm_last_error()
      error stop 1
    end if
  end subroutine
end program
