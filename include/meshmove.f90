! meshmove.f90: Fortran bindings of the meshmove C API (include/meshmove.h), shipped with the
! library. Two modules, as nlopt-f and fgsl do:
!   meshmove_c  raw bind(c) interfaces, one per C function, and named constants for the enums
!   meshmove    a thin handle layer: derived types holding a private c_ptr, explicit create/free,
!               1-based indices and components, arrays taken `contiguous` (a section is copied
!               in and out by the compiler, never passed as a bare address) and checked against
!               the sizes they are passed with, and optional `stat` and `errmsg` arguments on
!               every fallible routine; when `stat` is absent and the call fails, the routine
!               stops with the message (error stop).
! tests/fortran_interfaces.rs checks the interfaces, bind(c) types and constants against
! meshmove.h; tests/fortran/bad_sizes.f90 the size checks.
module meshmove_c
  use, intrinsic :: iso_c_binding
  implicit none (type, external)
  public

  ! meshmove_status
  integer(c_int32_t), parameter :: MESHMOVE_STATUS_OK = 0, MESHMOVE_STATUS_NULL_POINTER = 1, &
    MESHMOVE_STATUS_INVALID_HANDLE = 2, MESHMOVE_STATUS_INVALID_ARGUMENT = 3, &
    MESHMOVE_STATUS_INVALID_MESH = 4, MESHMOVE_STATUS_INVALID_BCS = 5, MESHMOVE_STATUS_ILL_POSED = 6, &
    MESHMOVE_STATUS_COARSENING = 7, MESHMOVE_STATUS_DIVERGED = 8, MESHMOVE_STATUS_IO = 9, &
    MESHMOVE_STATUS_BUFFER_TOO_SMALL = 10, MESHMOVE_STATUS_PANIC = 11, MESHMOVE_STATUS_NOT_CONVERGED = 12, &
    MESHMOVE_STATUS_TANGLED = 13, MESHMOVE_STATUS_INVERTED = 14, MESHMOVE_STATUS_BUSY = 15
  ! upper bounds of counts and options (MESHMOVE_MAX_* in meshmove.h)
  integer(c_int32_t), parameter :: MESHMOVE_MAX_STEPS = 1000000, MESHMOVE_MAX_CYCLES = 1000000, &
    MESHMOVE_MAX_CHEB_DEGREE = 64, MESHMOVE_MAX_THREADS = 1024, MESHMOVE_MAX_SUBSTEPS = 1048576, &
    MESHMOVE_MAX_VERTICES = 1073741823, MESHMOVE_MAX_CELLS = 715827882
  ! meshmove_method, meshmove_mode, meshmove_criterion
  integer(c_int32_t), parameter :: MESHMOVE_METHOD_BIHARMONIC = 0, MESHMOVE_METHOD_LAPLACIAN = 1, &
    MESHMOVE_METHOD_SPRING = 2
  integer(c_int32_t), parameter :: MESHMOVE_MODE_DEFAULT = 0, MESHMOVE_MODE_PAPER_FAITHFUL = 1
  integer(c_int32_t), parameter :: MESHMOVE_CRITERION_RELATIVE_RESIDUAL = 0, MESHMOVE_CRITERION_MAX_CORRECTION = 1
  ! meshmove_kind, meshmove_interface
  integer(c_int32_t), parameter :: MESHMOVE_KIND_FIXED = 0, MESHMOVE_KIND_CLAMPED = 1, MESHMOVE_KIND_FREE = 2
  integer(c_int32_t), parameter :: MESHMOVE_INTERFACE_SEPARATE = 0, MESHMOVE_INTERFACE_CONTINUOUS = 1
  ! meshmove_reference
  integer(c_int32_t), parameter :: MESHMOVE_REFERENCE_INCREMENTAL = 0, MESHMOVE_REFERENCE_ORIGINAL = 1
  ! patches of the built-in case meshes
  integer(c_int32_t), parameter :: MESHMOVE_FS_BOTTOM = 1, MESHMOVE_FS_RIGHT = 2, MESHMOVE_FS_TOP = 3, &
    MESHMOVE_FS_LEFT = 4
  integer(c_int32_t), parameter :: MESHMOVE_IF_BOTTOM = 1, MESHMOVE_IF_RIGHT = 2, MESHMOVE_IF_INTERFACE = 3, &
    MESHMOVE_IF_LEFT = 4, MESHMOVE_IF_TOP = 5
  integer(c_int32_t), parameter :: MESHMOVE_CH_WALL = 1, MESHMOVE_CH_CYLINDER = 2
  integer(c_int32_t), parameter :: MESHMOVE_VERSION_MAJOR = 0, MESHMOVE_VERSION_MINOR = 1, &
    MESHMOVE_VERSION_PATCH = 0

  type, bind(c) :: meshmove_options
    integer(c_int32_t) :: method, mode, criterion, threads
    real(c_double) :: tol
    integer(c_int32_t) :: max_cycles, cheb_degree
    real(c_double) :: cheb_lower_ratio
  end type
  type, bind(c) :: meshmove_report
    integer(c_int32_t) :: cycles
    real(c_double) :: max_correction, rel_residual, seconds
    integer(c_int32_t) :: converged
  end type
  type, bind(c) :: meshmove_quality
    integer(c_int32_t) :: inverted
    real(c_double) :: min_area_ratio, max_area_ratio, min_angle_deg
  end type
  type, bind(c) :: meshmove_step_report
    integer(c_int32_t) :: step, substep
    real(c_double) :: fraction
    integer(c_int32_t) :: cycles
    real(c_double) :: rel_residual
    integer(c_int32_t) :: converged, rebuilt, inverted
    real(c_double) :: min_volume_ratio, min_angle_deg, seconds
    integer(c_int32_t) :: accepted
  end type

  interface
    type(c_ptr) function meshmove_last_error() bind(c)
      import :: c_ptr
    end function
    type(c_ptr) function meshmove_status_name(status) bind(c)
      import :: c_ptr, c_int32_t
      integer(c_int32_t), value :: status
    end function
    integer(c_int32_t) function meshmove_last_error_message(buf, buf_len, needed) bind(c)
      import :: c_int32_t, c_char, c_size_t
      character(kind=c_char), intent(out) :: buf(*)
      integer(c_size_t), value :: buf_len
      integer(c_size_t), intent(out) :: needed
    end function
    integer(c_int32_t) function meshmove_version(major, minor, patch) bind(c)
      import :: c_int32_t
      integer(c_int32_t), intent(out) :: major, minor, patch
    end function
    integer(c_int32_t) function meshmove_options_default(options) bind(c)
      import :: c_int32_t, meshmove_options
      type(meshmove_options), intent(out) :: options
    end function
    integer(c_int32_t) function meshmove_mesh_create(num_vertices, coords, num_cells, cells, index_base, &
        num_tagged, tagged_edges, tagged_patches, regions, out) bind(c)
      import :: c_int32_t, c_double, c_ptr
      integer(c_int32_t), value :: num_vertices, num_cells, index_base, num_tagged
      real(c_double), intent(in) :: coords(*)
      integer(c_int32_t), intent(in) :: cells(*), tagged_edges(*), tagged_patches(*)
      type(c_ptr), value :: regions
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_mesh_create_case(name, h, out) bind(c)
      import :: c_int32_t, c_char, c_double, c_ptr
      character(kind=c_char), intent(in) :: name(*)
      real(c_double), value :: h
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_mesh_read_msh(path, out) bind(c)
      import :: c_int32_t, c_char, c_ptr
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_mesh_free(mesh) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
    end function
    integer(c_int32_t) function meshmove_mesh_sizes(mesh, num_vertices, num_cells) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), intent(out) :: num_vertices, num_cells
    end function
    integer(c_int32_t) function meshmove_mesh_get_coords(mesh, len, coords) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: len
      real(c_double), intent(out) :: coords(*)
    end function
    integer(c_int32_t) function meshmove_mesh_get_cells(mesh, index_base, len, cells) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: index_base, len
      integer(c_int32_t), intent(out) :: cells(*)
    end function
    integer(c_int32_t) function meshmove_mesh_get_regions(mesh, len, regions) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: len
      integer(c_int32_t), intent(out) :: regions(*)
    end function
    integer(c_int32_t) function meshmove_mesh_patch_vertices(mesh, patch, index_base, capacity, vertices, count) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: patch, index_base, capacity
      integer(c_int32_t), intent(out) :: vertices(*), count
    end function
    integer(c_int32_t) function meshmove_mesh_write_vtu(mesh, path, len, displacement) bind(c)
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: mesh, displacement
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t), value :: len
    end function
    integer(c_int32_t) function meshmove_bcs_create(out) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_bcs_free(bcs) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: bcs
    end function
    integer(c_int32_t) function meshmove_bcs_set_kind(bcs, patch, component, kind) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch, component, kind
    end function
    integer(c_int32_t) function meshmove_bcs_set_kinds(bcs, patch, kind) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch, kind
    end function
    integer(c_int32_t) function meshmove_bcs_set_default_kind(bcs, kind) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: kind
    end function
    integer(c_int32_t) function meshmove_bcs_link_periodic(bcs, patch_a, patch_b, dx, dy, tol) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch_a, patch_b
      real(c_double), value :: dx, dy, tol
    end function
    integer(c_int32_t) function meshmove_bcs_link_pairs(bcs, num_pairs, pairs, index_base) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: num_pairs, index_base
      integer(c_int32_t), intent(in) :: pairs(*)
    end function
    integer(c_int32_t) function meshmove_bcs_set_interface(bcs, patch, variant) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch, variant
    end function
    integer(c_int32_t) function meshmove_solver_create(mesh, bcs, options, out) bind(c)
      import :: c_int32_t, c_ptr, meshmove_options
      type(c_ptr), value :: mesh, bcs
      type(meshmove_options), intent(in) :: options
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_solver_free(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
    end function
    integer(c_int32_t) function meshmove_solver_sizes(solver, num_vertices, num_levels) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
      integer(c_int32_t), intent(out) :: num_vertices, num_levels
    end function
    integer(c_int32_t) function meshmove_solver_set_rigid_motion(solver, patch, tx, ty, angle, cx, cy) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: patch
      real(c_double), value :: tx, ty, angle, cx, cy
    end function
    integer(c_int32_t) function meshmove_solver_clear_rigid_motions(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
    end function
    integer(c_int32_t) function meshmove_solver_solve(solver, len, prescribed, guess, displacement, report) bind(c)
      import :: c_int32_t, c_ptr, c_double, meshmove_report
      type(c_ptr), value :: solver, guess
      integer(c_int32_t), value :: len
      real(c_double), intent(in) :: prescribed(*)
      real(c_double), intent(out) :: displacement(*)
      type(meshmove_report), intent(out) :: report
    end function
    integer(c_int32_t) function meshmove_solver_cycle(solver, len, prescribed, displacement, report) bind(c)
      import :: c_int32_t, c_ptr, c_double, meshmove_report
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(in) :: prescribed(*)
      real(c_double), intent(inout) :: displacement(*)
      type(meshmove_report), intent(out) :: report
    end function
    integer(c_int32_t) function meshmove_solver_move(solver, len, boundary_displacement, coords, report, quality) bind(c)
      import :: c_int32_t, c_ptr, c_double, meshmove_report, meshmove_quality
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(in) :: boundary_displacement(*)
      real(c_double), intent(inout) :: coords(*)
      type(meshmove_report), intent(out) :: report
      type(meshmove_quality), intent(out) :: quality
    end function
    integer(c_int32_t) function meshmove_solver_move_in_steps(solver, len, prescribed, steps, num_reports, reports) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len, steps, num_reports
      real(c_double), intent(in) :: prescribed(*)
      type(c_ptr), value :: reports
    end function
    integer(c_int32_t) function meshmove_solver_step_reports(solver, capacity, reports, count) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver, reports
      integer(c_int32_t), value :: capacity
      integer(c_int32_t), intent(out) :: count
    end function
    integer(c_int32_t) function meshmove_solver_set_substepping(solver, max_substeps, min_volume_ratio) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: max_substeps
      real(c_double), value :: min_volume_ratio
    end function
    integer(c_int32_t) function meshmove_solver_set_reference_mode(solver, mode) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: mode
    end function
    integer(c_int32_t) function meshmove_solver_set_reference(solver, len, coords) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(in) :: coords(*)
    end function
    integer(c_int32_t) function meshmove_solver_get_coords(solver, len, coords) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(out) :: coords(*)
    end function
    integer(c_int32_t) function meshmove_solver_get_displacement(solver, len, displacement) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(out) :: displacement(*)
    end function
    integer(c_int32_t) function meshmove_solver_quality(solver, len, displacement, quality) bind(c)
      import :: c_int32_t, c_ptr, c_double, meshmove_quality
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(in) :: displacement(*)
      type(meshmove_quality), intent(out) :: quality
    end function
    integer(c_int32_t) function meshmove_solver_write_vtu(solver, path, len, displacement) bind(c)
      import :: c_int32_t, c_ptr, c_char
      type(c_ptr), value :: solver, displacement
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int32_t), value :: len
    end function
  end interface
end module meshmove_c


module meshmove
  use, intrinsic :: iso_c_binding
  use meshmove_c
  implicit none (type, external)
  private
  public :: meshmove_options, meshmove_report, meshmove_quality, meshmove_step_report, mm_mesh, mm_bcs, &
    mm_solver, mm_default_options, mm_last_error, mm_check
  ! the named constants of meshmove_c
  public :: MESHMOVE_STATUS_OK, MESHMOVE_STATUS_NULL_POINTER, MESHMOVE_STATUS_INVALID_HANDLE, &
    MESHMOVE_STATUS_INVALID_ARGUMENT, MESHMOVE_STATUS_INVALID_MESH, MESHMOVE_STATUS_INVALID_BCS, &
    MESHMOVE_STATUS_ILL_POSED, MESHMOVE_STATUS_COARSENING, MESHMOVE_STATUS_DIVERGED, MESHMOVE_STATUS_IO, &
    MESHMOVE_STATUS_BUFFER_TOO_SMALL, MESHMOVE_STATUS_PANIC, MESHMOVE_STATUS_NOT_CONVERGED, &
    MESHMOVE_STATUS_TANGLED, MESHMOVE_STATUS_INVERTED, MESHMOVE_STATUS_BUSY, MESHMOVE_MAX_STEPS, &
    MESHMOVE_MAX_CYCLES, MESHMOVE_MAX_CHEB_DEGREE, MESHMOVE_MAX_THREADS, MESHMOVE_MAX_SUBSTEPS, &
    MESHMOVE_MAX_VERTICES, MESHMOVE_MAX_CELLS, MESHMOVE_METHOD_BIHARMONIC, &
    MESHMOVE_METHOD_LAPLACIAN, MESHMOVE_METHOD_SPRING, MESHMOVE_MODE_DEFAULT, MESHMOVE_MODE_PAPER_FAITHFUL, &
    MESHMOVE_CRITERION_RELATIVE_RESIDUAL, MESHMOVE_CRITERION_MAX_CORRECTION, MESHMOVE_KIND_FIXED, &
    MESHMOVE_KIND_CLAMPED, MESHMOVE_KIND_FREE, MESHMOVE_INTERFACE_SEPARATE, MESHMOVE_INTERFACE_CONTINUOUS, &
    MESHMOVE_REFERENCE_INCREMENTAL, MESHMOVE_REFERENCE_ORIGINAL, MESHMOVE_FS_BOTTOM, MESHMOVE_FS_RIGHT, &
    MESHMOVE_FS_TOP, MESHMOVE_FS_LEFT, MESHMOVE_IF_BOTTOM, &
    MESHMOVE_IF_RIGHT, MESHMOVE_IF_INTERFACE, MESHMOVE_IF_LEFT, MESHMOVE_IF_TOP, MESHMOVE_CH_WALL, &
    MESHMOVE_CH_CYLINDER

  !> A mesh. Vertex indices in and out are 1-based.
  type :: mm_mesh
    private
    type(c_ptr) :: h = c_null_ptr
  contains
    procedure :: create_case => mesh_create_case
    procedure :: create => mesh_create
    procedure :: free => mesh_free
    procedure :: num_vertices => mesh_num_vertices
    procedure :: num_cells => mesh_num_cells
    procedure :: coords => mesh_coords
    procedure :: cells => mesh_cells
    procedure :: regions => mesh_regions
    procedure :: patch_vertices => mesh_patch_vertices
    procedure :: write_vtu => mesh_write_vtu
  end type

  !> Boundary conditions. Components are 1 = x, 2 = y.
  type :: mm_bcs
    private
    type(c_ptr) :: h = c_null_ptr
  contains
    procedure :: create => bcs_create
    procedure :: free => bcs_free
    procedure :: set_kind => bcs_set_kind
    procedure :: set_kinds => bcs_set_kinds
    procedure :: set_default_kind => bcs_set_default_kind
    procedure :: link_periodic => bcs_link_periodic
    procedure :: link_pairs => bcs_link_pairs
    procedure :: set_interface => bcs_set_interface
  end type

  !> A solver. Coordinates and displacements are arrays of shape (2, number of vertices).
  type :: mm_solver
    private
    type(c_ptr) :: h = c_null_ptr
    integer(c_int32_t) :: nv = 0
  contains
    procedure :: create => solver_create
    procedure :: free => solver_free
    procedure :: num_vertices => solver_num_vertices
    procedure :: num_levels => solver_num_levels
    procedure :: set_rigid_motion => solver_set_rigid_motion
    procedure :: clear_rigid_motions => solver_clear_rigid_motions
    procedure :: solve => solver_solve
    procedure :: cycle => solver_cycle
    procedure :: move => solver_move
    procedure :: move_in_steps => solver_move_in_steps
    procedure :: step_reports => solver_step_reports
    procedure :: set_reference => solver_set_reference
    procedure :: set_substepping => solver_set_substepping
    procedure :: set_reference_mode => solver_set_reference_mode
    procedure :: coords => solver_coords
    procedure :: displacement => solver_displacement
    procedure :: quality => solver_quality
    procedure :: write_vtu => solver_write_vtu
  end type

  !> The message of the last failure found by this module itself (a size it checked), until the
  !> next library call; mm_last_error returns it first. Shared by the threads of a program: with
  !> threads, ask for `errmsg` instead.
  character(len=:), allocatable :: f_msg

contains

  !> The message of the last failed call on this thread (or of the last size this module refused).
  function mm_last_error() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char) :: buf(1024)
    integer(c_size_t) :: needed
    integer(c_int32_t) :: s
    integer :: i, n
    if (allocated(f_msg)) then
      msg = f_msg
      return
    end if
    s = meshmove_last_error_message(buf, int(size(buf), c_size_t), needed)
    n = 0
    do while (n < size(buf))
      if (buf(n + 1) == c_null_char) exit
      n = n + 1
    end do
    allocate (character(len=n) :: msg)
    do i = 1, n
      msg(i:i) = buf(i)
    end do
  end function

  !> Stores status `s` in `stat` (and the message in `errmsg`) when present; otherwise stops with
  !> the message if `s` is not OK.
  subroutine mm_check(s, where, stat, errmsg)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (allocated(f_msg)) deallocate (f_msg)
    if (present(errmsg)) then
      if (s == MESHMOVE_STATUS_OK) then
        errmsg = ""
      else
        errmsg = mm_last_error()
      end if
    end if
    if (present(stat)) then
      stat = int(s)
    else if (s /= MESHMOVE_STATUS_OK) then
      error stop "meshmove: " // where // ": " // mm_last_error()
    end if
  end subroutine

  !> A failure found by this module before calling the library (status `s`, message `text`).
  subroutine fail(s, where, text, stat, errmsg)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: where, text
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    f_msg = "meshmove_" // where // ": " // text
    if (present(errmsg)) errmsg = f_msg
    if (present(stat)) then
      stat = int(s)
    else
      error stop "meshmove: " // f_msg
    end if
  end subroutine

  function str(i) result(s)
    integer, intent(in) :: i
    character(len=:), allocatable :: s
    character(len=24) :: b
    write (b, '(i0)') i
    s = trim(b)
  end function

  !> True (after `fail`) unless `a` has shape (2, nv).
  logical function bad_shape(a1, a2, nv, what, where, stat, errmsg) result(bad)
    integer, intent(in) :: a1, a2
    integer(c_int32_t), intent(in) :: nv
    character(*), intent(in) :: what, where
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    bad = a1 /= 2 .or. a2 /= nv
    if (bad) call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, where, what // " has shape (" // str(a1) // ", " // &
      str(a2) // "); the mesh has " // str(int(nv)) // " vertices, so (2, " // str(int(nv)) // ") is needed", &
      stat, errmsg)
  end function

  function cstr(s) result(c)
    character(*), intent(in) :: s
    character(kind=c_char, len=len_trim(s) + 1) :: c
    c = trim(s) // c_null_char
  end function

  function mm_default_options() result(o)
    type(meshmove_options) :: o
    call mm_check(meshmove_options_default(o), "options_default")
  end function

  ! ---- mesh ----------------------------------------------------------------------------------

  subroutine mesh_create_case(self, name, h, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    character(*), intent(in) :: name
    real(c_double), intent(in) :: h
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_mesh_create_case(cstr(name), h, self%h), "mesh_create_case", stat, errmsg)
  end subroutine

  !> coords(2, nv); cells(3, nc) 1-based; tagged(2, nt) 1-based with patches(nt); regions(nc) optional.
  subroutine mesh_create(self, coords, cells, tagged, patches, regions, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    real(c_double), intent(in), contiguous :: coords(:, :)
    integer(c_int32_t), intent(in), contiguous :: cells(:, :), tagged(:, :), patches(:)
    integer(c_int32_t), intent(in), contiguous, target, optional :: regions(:)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    character(*), parameter :: w = "mesh_create"
    type(c_ptr) :: r
    integer(c_int32_t), target :: none(1)
    r = c_null_ptr
    if (size(coords, 1) /= 2) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "coords has " // str(size(coords, 1)) // &
        " rows; it must be coords(2, number of vertices)", stat, errmsg)
      return
    end if
    if (size(cells, 1) /= 3) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "cells has " // str(size(cells, 1)) // &
        " rows; it must be cells(3, number of cells)", stat, errmsg)
      return
    end if
    if (size(tagged, 1) /= 2 .or. size(tagged, 2) /= size(patches)) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "tagged has shape (" // str(size(tagged, 1)) // ", " // &
        str(size(tagged, 2)) // ") and patches has " // str(size(patches)) // &
        " entries; tagged(2, n) needs patches(n)", stat, errmsg)
      return
    end if
    if (size(coords, 2) > MESHMOVE_MAX_VERTICES .or. size(cells, 2) > MESHMOVE_MAX_CELLS) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "more than MESHMOVE_MAX_VERTICES vertices or " // &
        "MESHMOVE_MAX_CELLS cells", stat, errmsg)
      return
    end if
    if (present(regions)) then
      if (size(regions) /= size(cells, 2)) then
        call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "regions has " // str(size(regions)) // &
          " entries; there are " // str(size(cells, 2)) // " cells", stat, errmsg)
        return
      end if
      if (size(regions) > 0) r = c_loc(regions)
    end if
    none = 0
    if (size(patches) == 0) then
      call mm_check(meshmove_mesh_create(int(size(coords, 2), c_int32_t), coords, int(size(cells, 2), c_int32_t), &
        cells, 1_c_int32_t, 0_c_int32_t, none, none, r, self%h), w, stat, errmsg)
    else
      call mm_check(meshmove_mesh_create(int(size(coords, 2), c_int32_t), coords, int(size(cells, 2), c_int32_t), &
        cells, 1_c_int32_t, int(size(patches), c_int32_t), tagged, patches, r, self%h), w, stat, errmsg)
    end if
  end subroutine

  subroutine mesh_free(self, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (c_associated(self%h)) call mm_check(meshmove_mesh_free(self%h), "mesh_free", stat, errmsg)
    self%h = c_null_ptr
  end subroutine

  integer(c_int32_t) function mesh_num_vertices(self, stat, errmsg) result(n)
    class(mm_mesh), intent(in) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: nc
    n = 0
    nc = 0
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes", stat, errmsg)
  end function

  integer(c_int32_t) function mesh_num_cells(self, stat, errmsg) result(nc)
    class(mm_mesh), intent(in) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n
    n = 0
    nc = 0
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes", stat, errmsg)
  end function

  !> Coordinates as xy(2, nv).
  subroutine mesh_coords(self, xy, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    real(c_double), allocatable, intent(out) :: xy(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n, nc
    n = 0
    nc = 0
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes", stat, errmsg)
    allocate (xy(2, n))
    if (n == 0) return
    call mm_check(meshmove_mesh_get_coords(self%h, int(size(xy), c_int32_t), xy), "mesh_get_coords", stat, errmsg)
  end subroutine

  !> Cells as c(3, nc), 1-based.
  subroutine mesh_cells(self, c, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: c(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n, nc
    n = 0
    nc = 0
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes", stat, errmsg)
    allocate (c(3, nc))
    if (nc == 0) return
    call mm_check(meshmove_mesh_get_cells(self%h, 1_c_int32_t, int(size(c), c_int32_t), c), "mesh_get_cells", &
      stat, errmsg)
  end subroutine

  subroutine mesh_regions(self, r, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: r(:)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n, nc
    n = 0
    nc = 0
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes", stat, errmsg)
    allocate (r(nc))
    if (nc == 0) return
    call mm_check(meshmove_mesh_get_regions(self%h, int(size(r), c_int32_t), r), "mesh_get_regions", stat, errmsg)
  end subroutine

  !> Vertices (1-based) on a patch.
  subroutine mesh_patch_vertices(self, patch, v, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(in) :: patch
    integer(c_int32_t), allocatable, intent(out) :: v(:)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: buf(1), n, cap, s
    n = 0
    s = meshmove_mesh_patch_vertices(self%h, patch, 1_c_int32_t, 0_c_int32_t, buf, n)
    if (s /= MESHMOVE_STATUS_OK .and. s /= MESHMOVE_STATUS_BUFFER_TOO_SMALL) then
      allocate (v(0))
      call mm_check(s, "mesh_patch_vertices", stat, errmsg)
      return
    end if
    cap = n
    allocate (v(max(cap, 1_c_int32_t)))
    call mm_check(meshmove_mesh_patch_vertices(self%h, patch, 1_c_int32_t, cap, v, n), "mesh_patch_vertices", &
      stat, errmsg)
    if (size(v) /= n) v = v(1:n)
  end subroutine

  !> Writes the mesh moved by d(2, nv) (absent: the mesh itself) as a .vtu file.
  subroutine mesh_write_vtu(self, path, d, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    character(*), intent(in) :: path
    real(c_double), intent(in), contiguous, target, optional :: d(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n
    if (present(d)) then
      n = self%num_vertices(stat, errmsg)
      if (present(stat)) then
        if (stat /= MESHMOVE_STATUS_OK) return
      end if
      if (bad_shape(size(d, 1), size(d, 2), n, "d", "mesh_write_vtu", stat, errmsg)) return
      call mm_check(meshmove_mesh_write_vtu(self%h, cstr(path), int(size(d), c_int32_t), c_loc(d)), &
        "mesh_write_vtu", stat, errmsg)
    else
      call mm_check(meshmove_mesh_write_vtu(self%h, cstr(path), 0_c_int32_t, c_null_ptr), "mesh_write_vtu", stat, errmsg)
    end if
  end subroutine

  ! ---- boundary conditions -------------------------------------------------------------------

  subroutine bcs_create(self, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_bcs_create(self%h), "bcs_create", stat, errmsg)
  end subroutine

  subroutine bcs_free(self, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (c_associated(self%h)) call mm_check(meshmove_bcs_free(self%h), "bcs_free", stat, errmsg)
    self%h = c_null_ptr
  end subroutine

  !> component 1 = x, 2 = y (Fortran numbering).
  subroutine bcs_set_kind(self, patch, component, kind, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, component, kind
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (component < 1 .or. component > 2) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, "bcs_set_kind", "component " // str(int(component)) // &
        " does not exist in 2D (1 = x, 2 = y)", stat, errmsg)
      return
    end if
    call mm_check(meshmove_bcs_set_kind(self%h, patch, component - 1_c_int32_t, kind), "bcs_set_kind", stat, errmsg)
  end subroutine

  subroutine bcs_set_kinds(self, patch, kind, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, kind
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_bcs_set_kinds(self%h, patch, kind), "bcs_set_kinds", stat, errmsg)
  end subroutine

  subroutine bcs_set_default_kind(self, kind, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: kind
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_bcs_set_default_kind(self%h, kind), "bcs_set_default_kind", stat, errmsg)
  end subroutine

  subroutine bcs_link_periodic(self, a, b, dx, dy, tol, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: a, b
    real(c_double), intent(in) :: dx, dy, tol
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_bcs_link_periodic(self%h, a, b, dx, dy, tol), "bcs_link_periodic", stat, errmsg)
  end subroutine

  !> pairs(2, n): 1-based vertex pairs that become one unknown.
  subroutine bcs_link_pairs(self, pairs, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in), contiguous :: pairs(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (size(pairs, 1) /= 2) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, "bcs_link_pairs", "pairs has " // str(size(pairs, 1)) // &
        " rows; it must be pairs(2, number of pairs)", stat, errmsg)
      return
    end if
    call mm_check(meshmove_bcs_link_pairs(self%h, int(size(pairs, 2), c_int32_t), pairs, 1_c_int32_t), &
      "bcs_link_pairs", stat, errmsg)
  end subroutine

  subroutine bcs_set_interface(self, patch, variant, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, variant
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_bcs_set_interface(self%h, patch, variant), "bcs_set_interface", stat, errmsg)
  end subroutine

  ! ---- solver --------------------------------------------------------------------------------

  subroutine solver_create(self, mesh, bcs, options, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    type(mm_mesh), intent(in) :: mesh
    type(mm_bcs), intent(in) :: bcs
    type(meshmove_options), intent(in), optional :: options
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_options) :: o
    integer(c_int32_t) :: s, levels
    if (present(options)) then
      o = options
    else
      o = mm_default_options()
    end if
    s = meshmove_solver_create(mesh%h, bcs%h, o, self%h)
    if (s == MESHMOVE_STATUS_OK) s = meshmove_solver_sizes(self%h, self%nv, levels)
    call mm_check(s, "solver_create", stat, errmsg)
  end subroutine

  subroutine solver_free(self, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (c_associated(self%h)) call mm_check(meshmove_solver_free(self%h), "solver_free", stat, errmsg)
    self%h = c_null_ptr
    self%nv = 0
  end subroutine

  integer(c_int32_t) function solver_num_vertices(self) result(n)
    class(mm_solver), intent(in) :: self
    n = self%nv
  end function

  integer(c_int32_t) function solver_num_levels(self, stat, errmsg) result(levels)
    class(mm_solver), intent(in) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n
    n = 0
    levels = 0
    call mm_check(meshmove_solver_sizes(self%h, n, levels), "solver_sizes", stat, errmsg)
  end function

  !> Patch `patch` moves rigidly: rotation by `angle` (radians) about (cx, cy), then (tx, ty).
  subroutine solver_set_rigid_motion(self, patch, tx, ty, angle, cx, cy, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch
    real(c_double), intent(in) :: tx, ty, angle, cx, cy
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_solver_set_rigid_motion(self%h, patch, tx, ty, angle, cx, cy), "solver_set_rigid_motion", &
      stat, errmsg)
  end subroutine

  subroutine solver_clear_rigid_motions(self, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_solver_clear_rigid_motions(self%h), "solver_clear_rigid_motions", stat, errmsg)
  end subroutine

  !> d(2, nv): prescribed displacement in, solution out. With MESHMOVE_STATUS_NOT_CONVERGED in
  !> `stat`, d holds the unconverged solution.
  subroutine solver_solve(self, d, report, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(inout), contiguous :: d(:, :)
    type(meshmove_report), intent(out), optional :: report
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_report) :: r
    real(c_double), allocatable :: p(:, :)
    if (bad_shape(size(d, 1), size(d, 2), self%nv, "d", "solver_solve", stat, errmsg)) return
    allocate (p, source=d)
    call mm_check(meshmove_solver_solve(self%h, int(size(d), c_int32_t), p, c_null_ptr, d, r), "solver_solve", &
      stat, errmsg)
    if (present(report)) report = r
  end subroutine

  !> One multigrid cycle from d(2, nv) (read and overwritten); prescribed(2, nv).
  subroutine solver_cycle(self, prescribed, d, report, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: prescribed(:, :)
    real(c_double), intent(inout), contiguous :: d(:, :)
    type(meshmove_report), intent(out), optional :: report
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_report) :: r
    if (bad_shape(size(prescribed, 1), size(prescribed, 2), self%nv, "prescribed", "solver_cycle", stat, errmsg)) return
    if (bad_shape(size(d, 1), size(d, 2), self%nv, "d", "solver_cycle", stat, errmsg)) return
    call mm_check(meshmove_solver_cycle(self%h, int(size(d), c_int32_t), prescribed, d, r), "solver_cycle", stat, errmsg)
    if (present(report)) report = r
  end subroutine

  !> The drop-in call: xy(2, nv) updated in place from the boundary displacement bd(2, nv).
  !> MESHMOVE_STATUS_INVERTED in `stat`: xy holds the moved mesh, `quality` the inverted cells.
  subroutine solver_move(self, bd, xy, report, quality, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: bd(:, :)
    real(c_double), intent(inout), contiguous :: xy(:, :)
    type(meshmove_report), intent(out), optional :: report
    type(meshmove_quality), intent(out), optional :: quality
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_report) :: r
    type(meshmove_quality) :: q
    if (bad_shape(size(bd, 1), size(bd, 2), self%nv, "bd", "solver_move", stat, errmsg)) return
    if (bad_shape(size(xy, 1), size(xy, 2), self%nv, "xy", "solver_move", stat, errmsg)) return
    call mm_check(meshmove_solver_move(self%h, int(size(xy), c_int32_t), bd, xy, r, q), "solver_move", stat, errmsg)
    if (present(report)) report = r
    if (present(quality)) quality = q
  end subroutine

  !> Moves the boundary to d(2, nv) in `steps` equal steps (1 ≤ steps ≤ MESHMOVE_MAX_STEPS).
  !> `reports` (optional) receives the first size(reports) step reports.
  subroutine solver_move_in_steps(self, d, steps, reports, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: d(:, :)
    integer(c_int32_t), intent(in) :: steps
    type(meshmove_step_report), intent(out), contiguous, target, optional :: reports(:)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(c_ptr) :: rp
    integer(c_int32_t) :: nr
    rp = c_null_ptr
    nr = 0
    if (bad_shape(size(d, 1), size(d, 2), self%nv, "d", "solver_move_in_steps", stat, errmsg)) return
    if (present(reports)) then
      if (size(reports) > 0) then
        rp = c_loc(reports)
        nr = int(size(reports), c_int32_t)
      end if
    end if
    call mm_check(meshmove_solver_move_in_steps(self%h, int(size(d), c_int32_t), d, steps, nr, rp), &
      "solver_move_in_steps", stat, errmsg)
  end subroutine

  !> The step reports of the last move_in_steps (kept after a failure too).
  subroutine solver_step_reports(self, reports, stat, errmsg)
    class(mm_solver), intent(in) :: self
    type(meshmove_step_report), allocatable, target, intent(out) :: reports(:)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n, cap, s
    n = 0
    s = meshmove_solver_step_reports(self%h, 0_c_int32_t, c_null_ptr, n)
    if (s /= MESHMOVE_STATUS_OK .and. s /= MESHMOVE_STATUS_BUFFER_TOO_SMALL) then
      allocate (reports(0))
      call mm_check(s, "solver_step_reports", stat, errmsg)
      return
    end if
    allocate (reports(n))
    if (n == 0) then
      call mm_check(s, "solver_step_reports", stat, errmsg)
      return
    end if
    cap = n
    call mm_check(meshmove_solver_step_reports(self%h, cap, c_loc(reports), n), "solver_step_reports", stat, errmsg)
  end subroutine

  !> Automatic sub-stepping: a step that would invert a cell, fall below min_volume_ratio or not
  !> converge is split in halves, down to 1/max_substeps of the step (0 or 1: no splitting).
  subroutine solver_set_substepping(self, max_substeps, min_volume_ratio, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(in) :: max_substeps
    real(c_double), intent(in) :: min_volume_ratio
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_solver_set_substepping(self%h, max_substeps, min_volume_ratio), "solver_set_substepping", &
      stat, errmsg)
  end subroutine

  !> What each later step is solved from: MESHMOVE_REFERENCE_INCREMENTAL or _ORIGINAL.
  subroutine solver_set_reference_mode(self, mode, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(in) :: mode
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call mm_check(meshmove_solver_set_reference_mode(self%h, mode), "solver_set_reference_mode", stat, errmsg)
  end subroutine

  !> Makes xy(2, nv) the solver's reference mesh.
  subroutine solver_set_reference(self, xy, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: xy(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (bad_shape(size(xy, 1), size(xy, 2), self%nv, "xy", "solver_set_reference", stat, errmsg)) return
    call mm_check(meshmove_solver_set_reference(self%h, int(size(xy), c_int32_t), xy), "solver_set_reference", &
      stat, errmsg)
  end subroutine

  !> The reference coordinates as xy(2, nv).
  subroutine solver_coords(self, xy, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), allocatable, intent(out) :: xy(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    allocate (xy(2, self%nv))
    call mm_check(meshmove_solver_get_coords(self%h, int(size(xy), c_int32_t), xy), "solver_get_coords", stat, errmsg)
  end subroutine

  !> The displacement of the last solve, cycle or move as d(2, nv).
  subroutine solver_displacement(self, d, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), allocatable, intent(out) :: d(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    allocate (d(2, self%nv))
    call mm_check(meshmove_solver_get_displacement(self%h, int(size(d), c_int32_t), d), "solver_get_displacement", &
      stat, errmsg)
  end subroutine

  !> Quality of the reference mesh moved by d(2, nv).
  subroutine solver_quality(self, d, quality, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), intent(in), contiguous :: d(:, :)
    type(meshmove_quality), intent(out) :: quality
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (bad_shape(size(d, 1), size(d, 2), self%nv, "d", "solver_quality", stat, errmsg)) return
    call mm_check(meshmove_solver_quality(self%h, int(size(d), c_int32_t), d, quality), "solver_quality", stat, errmsg)
  end subroutine

  !> Writes the reference mesh moved by d(2, nv) (absent: the reference itself).
  subroutine solver_write_vtu(self, path, d, stat, errmsg)
    class(mm_solver), intent(in) :: self
    character(*), intent(in) :: path
    real(c_double), intent(in), contiguous, target, optional :: d(:, :)
    integer, intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(d)) then
      if (bad_shape(size(d, 1), size(d, 2), self%nv, "d", "solver_write_vtu", stat, errmsg)) return
      call mm_check(meshmove_solver_write_vtu(self%h, cstr(path), int(size(d), c_int32_t), c_loc(d)), &
        "solver_write_vtu", stat, errmsg)
    else
      call mm_check(meshmove_solver_write_vtu(self%h, cstr(path), 0_c_int32_t, c_null_ptr), "solver_write_vtu", &
        stat, errmsg)
    end if
  end subroutine
end module meshmove
