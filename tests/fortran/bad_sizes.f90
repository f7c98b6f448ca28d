! The Fortran module checks every size before calling the library and takes contiguous copies of
! array sections: mismatched sizes give a status and a message naming the arrays (1-based
! components, offsets and indices, Fortran shapes), sections give the same results as contiguous
! arrays, and an unbounded step count is refused before anything is allocated. The generic mesh
! call, the options, the rigid motion and the mesh's lists are checked the same way.
program bad_sizes
  use, intrinsic :: iso_c_binding
  use meshmove
  implicit none (type, external)
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  type(mm_options) :: options
  type(mm_mesh) :: generic
  real(c_double) :: xy(2, 5), d(2, 5), big(4, 5), rev(2, 5), short(2, 4)
  integer(c_int32_t) :: cells(3, 4), tagged(2, 1), regions(3), tri(4), sizes(6)
  integer(c_int32_t), allocatable :: types(:), conn(:), offsets(:), patches(:)
  character(len=:), allocatable :: msg
  integer :: stat, failures

  failures = 0
  d = 0
  ! a solver never created: the call says so (not "0 vertices in 0D")
  call solver%move_in_steps(d, 1, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_NULL_POINTER, msg, "never created")
  xy = reshape([0d0, 0d0, 1d0, 0d0, 1d0, 1d0, 0d0, 1d0, 0.5d0, 0.5d0], [2, 5])
  cells = reshape([1, 2, 5, 2, 3, 5, 3, 4, 5, 4, 1, 5], [3, 4])
  tagged = reshape([2, 3], [2, 1])
  regions = 0
  tri = MESHMOVE_CELL_TYPE_TRIANGLE

  call mesh%create_triangles(xy, cells, tagged, [2, 2], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "patches has 2")
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, mm_last_error(), "tagged has shape (2, 1)")
  call mesh%create_triangles(xy, cells, tagged, [2], regions=regions, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "regions has 3 entries; there are 4 cells")
  call mesh%create_triangles(xy(:, 1:4), cells, tagged, [2], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_MESH, msg, "")
  call mesh%create_triangles(xy, cells, tagged, [2], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")

  ! the generic call: Fortran sizes checked here, offsets 1-based, the rest by the library
  call generic%create(xy, tri, reshape(cells, [12]), face_connectivity=[2, 3], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "face_connectivity and face_patch go together")
  call generic%create(xy, tri, reshape(cells, [12]), cell_offsets=[1, 4, 7, 10], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "cell_offsets (number of cells + 1) has 4 entries; 5")
  call generic%create(xy, tri, reshape(cells, [12]), cell_offsets=[1, 4, 8, 10, 13], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "give cell 2 4 vertices")
  call generic%create(xy, tri, reshape(cells, [12]), regions=regions, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "regions (one per cell) has 3 entries")
  call generic%create(xy, tri, reshape(cells, [11]), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "12 vertex indices are needed, 11 were given")
  call generic%create(xy, tri, reshape(cells, [12]), face_connectivity=[2, 6], face_patch=[2], stat=stat, &
    errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_MESH, msg, "refers to vertex index 6, outside 1..6")
  call generic%create(xy, tri, reshape(cells, [12]), face_connectivity=[2, 3], face_patch=[2], &
    cell_offsets=[1, 4, 7, 10, 13], face_offsets=[1, 3], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call generic%cells(types, conn, offsets, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  if (any(types /= tri) .or. any(offsets /= [1, 4, 7, 10, 13]) .or. minval(conn) /= 1 .or. maxval(conn) /= 5) then
    print *, "FAIL: cells read back", types, offsets, conn
    failures = failures + 1
  end if
  call generic%faces(patches, conn, offsets, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  if (size(patches) /= 4 .or. count(patches == 2) /= 1 .or. any(offsets /= [1, 3, 5, 7, 9])) then
    print *, "FAIL: faces read back", patches, offsets
    failures = failures + 1
  end if
  call generic%sizes(dim=sizes(1), num_vertices=sizes(2), num_cells=sizes(3), num_cell_vertices=sizes(4), &
    num_faces=sizes(5), num_face_vertices=sizes(6))
  if (any(sizes /= [2, 5, 4, 12, 4, 8])) then
    print *, "FAIL: sizes of the generic mesh", sizes
    failures = failures + 1
  end if
  if (generic%num_vertices() /= 5) then
    print *, "FAIL: num_vertices of the generic mesh"
    failures = failures + 1
  end if
  call generic%free()

  ! options: each setter checks its value
  call options%create()
  call options%set_method(7, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "method 7")
  call options%set_tol(-1d0, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "tol is -1")
  call options%set_threads(1, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")

  call bcs%create()
  call bcs%set_kind(2, 4, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "component 4 does not exist (1 = x, 2 = y, 3 = z)")
  ! z (component 3) is a component of 3D meshes: accepted, and ignored on a 2D mesh
  call bcs%set_kind(2, 3, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call bcs%set_kind(2, 0, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "component 0")
  call bcs%set_kind(2, 2, MESHMOVE_KIND_FIXED, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call bcs%link_pairs(reshape([1, 2, 3], [3, 1]), stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "pairs has 3 rows")
  call bcs%link_periodic(1, 2, [1d0, 0d0, 0d0, 0d0], 1d-9, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "dim is 4")
  call solver%create(mesh, bcs, options, stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call options%free()
  if (solver%dim() /= 2 .or. solver%num_vertices() /= 5) then
    print *, "FAIL: solver sizes"
    failures = failures + 1
  end if

  ! a rigid motion takes dim values (the angle alone in 2D)
  call solver%set_rigid_motion(2, [0d0, 0d0, 0d0], [0.1d0], [1d0, 0.5d0], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "translation (one per dimension) has 3 entries; 2")
  call solver%set_rigid_motion(2, [0d0, 0d0], [0d0, 0d0, 0.1d0], [1d0, 0.5d0], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "rotation (1 in 2D, 3 in 3D) has 3 entries; 1")
  call solver%set_rigid_motion(9, [0d0, 0d0], [0.1d0], [1d0, 0.5d0], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_INVALID_ARGUMENT, msg, "patch 9 is not in the mesh")
  call solver%set_rigid_motion(2, [0d0, 0d0], [0.1d0], [1d0, 0.5d0], stat=stat, errmsg=msg)
  call expect(stat, MESHMOVE_STATUS_OK, msg, "")
  call solver%clear_rigid_motions()

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
