! The Fortran module checks every size before calling the library and takes contiguous copies of
! array sections: mismatched sizes give a status and a message naming the arrays (1-based
! components, Fortran shapes), sections give the same results as contiguous arrays, and an
! unbounded step count is refused before anything is allocated.
program bad_sizes
  use, intrinsic :: iso_c_binding
  use meshmove
  implicit none (type, external)
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  real(c_double) :: xy(2, 5), d(2, 5), big(4, 5), rev(2, 5), short(2, 4)
  integer(c_int32_t) :: cells(3, 4), tagged(2, 1), regions(3)
  character(len=:), allocatable :: msg
  integer :: stat, failures

  failures = 0
  xy = reshape([0d0, 0d0, 1d0, 0d0, 1d0, 1d0, 0d0, 1d0, 0.5d0, 0.5d0], [2, 5])
  cells = reshape([1, 2, 5, 2, 3, 5, 3, 4, 5, 4, 1, 5], [3, 4])
  tagged = reshape([2, 3], [2, 1])
  regions = 0

  call mesh%create(xy, cells, tagged, [2, 2], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "patches has 2")
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, mm_last_error(), "tagged has shape (2, 1)")
  call mesh%create(xy, cells, tagged, [2], regions=regions, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "regions has 3 entries; there are 4 cells")
  call mesh%create(xy(:, 1:4), cells, tagged, [2], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_MESH, msg, "")
  call mesh%create(xy, cells, tagged, [2], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")

  call bcs%create()
  call bcs%set_kind(2, 3, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "component 3 does not exist in 2D (1 = x, 2 = y)")
  call bcs%set_kind(2, 0, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "component 0")
  call bcs%set_kind(2, 2, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call bcs%link_pairs(reshape([1, 2, 3], [3, 1]), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "pairs has 3 rows")
  call solver%create(mesh, bcs, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")

  ! the right side (vertices 2 and 3) moves right
  d = 0
  d(1, 2:3) = 0.1d0
  short = 0
  call solver%solve(short, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "d has shape (2, 4); the mesh has 5 vertices")
  call solver%move(d, short, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "xy has shape (2, 4)")

  ! a section with a stride gives what the contiguous array gives
  big = -7
  big(1:2, :) = d
  call solver%solve(d, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call solver%solve(big(1:2, :), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  if (any(big(1:2, :) /= d) .or. any(big(3:4, :) /= -7)) then
    print *, "FAIL: solve on big(1:2, :) differs from the contiguous solve"
    failures = failures + 1
  end if
  ! a reversed section is written as its values, not as the memory after it
  rev = d(:, 5:1:-1)
  call solver%write_vtu("bad_sizes_section.vtu", d(:, 5:1:-1), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call solver%write_vtu("bad_sizes_copy.vtu", rev, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  if (.not. same_file("bad_sizes_section.vtu", "bad_sizes_copy.vtu")) then
    print *, "FAIL: write_vtu of d(:, 5:1:-1) differs from write_vtu of its copy"
    failures = failures + 1
  end if
  call solver%write_vtu("bad_sizes_x.vtu", big(:, 1:2), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "d has shape (4, 2)")

  ! an unbounded step count fails at once (no automatic array of that size, no allocation)
  call solver%move_in_steps(d, huge(1_c_int32_t), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "steps is 2147483647")

  call solver%free()
  call bcs%free()
  call mesh%free()
  if (failures > 0) error stop "bad_sizes: failures"
  print '(a)', "bad_sizes: all checks passed"

contains

  subroutine expect(got, want, text, needle)
    integer, intent(in) :: got
    integer(c_int32_t), intent(in) :: want
    character(*), intent(in) :: text, needle
    if (got /= want) then
      print '(a, i0, a, i0, 2a)', "FAIL: status ", got, ", want ", want, ": ", text
      failures = failures + 1
    else if (index(text, needle) == 0) then
      print '(5a)', 'FAIL: message "', text, '" does not contain "', needle, '"'
      failures = failures + 1
    end if
  end subroutine

  logical function same_file(a, b)
    character(*), intent(in) :: a, b
    character(len=:), allocatable :: ca, cb
    same_file = .false.
    call slurp(a, ca)
    call slurp(b, cb)
    if (.not. (allocated(ca) .and. allocated(cb))) return
    same_file = len(ca) > 0 .and. ca == cb
  end function

  subroutine slurp(path, text)
    character(*), intent(in) :: path
    character(len=:), allocatable, intent(out) :: text
    integer :: u, n, ios
    open (newunit=u, file=path, access="stream", form="unformatted", status="old", iostat=ios)
    if (ios /= 0) return
    inquire (unit=u, size=n)
    allocate (character(len=n) :: text)
    read (u, iostat=ios) text
    close (u)
  end subroutine
end program
