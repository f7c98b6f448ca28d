! meshmove.f90: Fortran bindings of the meshmove C API (include/meshmove.h), shipped with the
! library. Two modules, as nlopt-f and fgsl do:
!   meshmove_c  raw bind(c) interfaces, one per C function, and named constants for the enums
!   meshmove    a thin handle layer: derived types holding a private c_ptr, explicit create/free,
!               1-based indices by default, and an optional `stat` argument on every fallible
!               routine; when `stat` is absent and the call fails, the routine stops with the
!               library's message (error stop).
! Keep in step with meshmove.h (the ctest Fortran examples exercise every binding used here).
module meshmove_c
  use, intrinsic :: iso_c_binding
  implicit none (type, external)
  public

  ! meshmove_status
  integer(c_int32_t), parameter :: MESHMOVE_STATUS_OK = 0, MESHMOVE_STATUS_NULL_POINTER = 1, &
    MESHMOVE_STATUS_INVALID_HANDLE = 2, MESHMOVE_STATUS_INVALID_ARGUMENT = 3, &
    MESHMOVE_STATUS_INVALID_MESH = 4, MESHMOVE_STATUS_INVALID_BCS = 5, MESHMOVE_STATUS_ILL_POSED = 6, &
    MESHMOVE_STATUS_COARSENING = 7, MESHMOVE_STATUS_DIVERGED = 8, MESHMOVE_STATUS_IO = 9, &
    MESHMOVE_STATUS_BUFFER_TOO_SMALL = 10, MESHMOVE_STATUS_PANIC = 11
  ! meshmove_method, meshmove_mode, meshmove_criterion
  integer(c_int32_t), parameter :: MESHMOVE_METHOD_BIHARMONIC = 0, MESHMOVE_METHOD_LAPLACIAN = 1, &
    MESHMOVE_METHOD_SPRING = 2
  integer(c_int32_t), parameter :: MESHMOVE_MODE_DEFAULT = 0, MESHMOVE_MODE_PAPER_FAITHFUL = 1
  integer(c_int32_t), parameter :: MESHMOVE_CRITERION_RELATIVE_RESIDUAL = 0, MESHMOVE_CRITERION_MAX_CORRECTION = 1
  ! meshmove_kind, meshmove_interface
  integer(c_int32_t), parameter :: MESHMOVE_KIND_FIXED = 0, MESHMOVE_KIND_CLAMPED = 1, MESHMOVE_KIND_FREE = 2
  integer(c_int32_t), parameter :: MESHMOVE_INTERFACE_SEPARATE = 0, MESHMOVE_INTERFACE_CONTINUOUS = 1
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

  interface
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
      import :: c_int32_t, c_ptr, c_double, meshmove_report
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len, steps, num_reports
      real(c_double), intent(in) :: prescribed(*)
      type(meshmove_report), intent(out) :: reports(*)
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
  public :: meshmove_options, meshmove_report, meshmove_quality, mm_mesh, mm_bcs, mm_solver, &
    mm_default_options, mm_last_error, mm_check
  ! the named constants of meshmove_c
  public :: MESHMOVE_STATUS_OK, MESHMOVE_STATUS_NULL_POINTER, MESHMOVE_STATUS_INVALID_HANDLE, &
    MESHMOVE_STATUS_INVALID_ARGUMENT, MESHMOVE_STATUS_INVALID_MESH, MESHMOVE_STATUS_INVALID_BCS, &
    MESHMOVE_STATUS_ILL_POSED, MESHMOVE_STATUS_COARSENING, MESHMOVE_STATUS_DIVERGED, MESHMOVE_STATUS_IO, &
    MESHMOVE_STATUS_BUFFER_TOO_SMALL, MESHMOVE_STATUS_PANIC, MESHMOVE_METHOD_BIHARMONIC, &
    MESHMOVE_METHOD_LAPLACIAN, MESHMOVE_METHOD_SPRING, MESHMOVE_MODE_DEFAULT, MESHMOVE_MODE_PAPER_FAITHFUL, &
    MESHMOVE_CRITERION_RELATIVE_RESIDUAL, MESHMOVE_CRITERION_MAX_CORRECTION, MESHMOVE_KIND_FIXED, &
    MESHMOVE_KIND_CLAMPED, MESHMOVE_KIND_FREE, MESHMOVE_INTERFACE_SEPARATE, MESHMOVE_INTERFACE_CONTINUOUS, &
    MESHMOVE_FS_BOTTOM, MESHMOVE_FS_RIGHT, MESHMOVE_FS_TOP, MESHMOVE_FS_LEFT, MESHMOVE_IF_BOTTOM, &
    MESHMOVE_IF_RIGHT, MESHMOVE_IF_INTERFACE, MESHMOVE_IF_LEFT, MESHMOVE_IF_TOP, MESHMOVE_CH_WALL, &
    MESHMOVE_CH_CYLINDER

  !> A mesh. Vertex indices in and out are 1-based unless a routine takes `index_base`.
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
  end type

  type :: mm_bcs
    private
    type(c_ptr) :: h = c_null_ptr
  contains
    procedure :: create => bcs_create
    procedure :: free => bcs_free
    procedure :: set_kind => bcs_set_kind
    procedure :: set_kinds => bcs_set_kinds
    procedure :: link_periodic => bcs_link_periodic
    procedure :: set_interface => bcs_set_interface
  end type

  type :: mm_solver
    private
    type(c_ptr) :: h = c_null_ptr
    integer(c_int32_t) :: nv = 0
  contains
    procedure :: create => solver_create
    procedure :: free => solver_free
    procedure :: solve => solver_solve
    procedure :: move => solver_move
    procedure :: move_in_steps => solver_move_in_steps
    procedure :: write_vtu => solver_write_vtu
  end type

contains

  !> The message of the last failed call on this thread.
  function mm_last_error() result(msg)
    character(len=:), allocatable :: msg
    character(kind=c_char) :: buf(1024)
    integer(c_size_t) :: needed
    integer(c_int32_t) :: s
    integer :: i, n
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

  !> Stores status `s` in `stat` when present; otherwise stops with the message if `s` is not OK.
  subroutine mm_check(s, where, stat)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: where
    integer, intent(out), optional :: stat
    if (present(stat)) then
      stat = int(s)
    else if (s /= MESHMOVE_STATUS_OK) then
      error stop "meshmove: " // where // ": " // mm_last_error()
    end if
  end subroutine

  function cstr(s) result(c)
    character(*), intent(in) :: s
    character(kind=c_char, len=len_trim(s) + 1) :: c
    c = trim(s) // c_null_char
  end function

  function mm_default_options() result(o)
    type(meshmove_options) :: o
    call mm_check(meshmove_options_default(o), "options_default")
  end function

  subroutine mesh_create_case(self, name, h, stat)
    class(mm_mesh), intent(inout) :: self
    character(*), intent(in) :: name
    real(c_double), intent(in) :: h
    integer, intent(out), optional :: stat
    call mm_check(meshmove_mesh_create_case(cstr(name), h, self%h), "mesh_create_case", stat)
  end subroutine

  !> coords(2, nv); cells(3, nc) 1-based; tagged(2, nt) 1-based with patches(nt); regions(nc) optional.
  subroutine mesh_create(self, coords, cells, tagged, patches, regions, stat)
    class(mm_mesh), intent(inout) :: self
    real(c_double), intent(in) :: coords(:, :)
    integer(c_int32_t), intent(in) :: cells(:, :), tagged(:, :), patches(:)
    integer(c_int32_t), intent(in), target, optional :: regions(:)
    integer, intent(out), optional :: stat
    type(c_ptr) :: r
    r = c_null_ptr
    if (present(regions)) r = c_loc(regions)
    call mm_check(meshmove_mesh_create(int(size(coords, 2), c_int32_t), coords, int(size(cells, 2), c_int32_t), &
      cells, 1_c_int32_t, int(size(patches), c_int32_t), tagged, patches, r, self%h), "mesh_create", stat)
  end subroutine

  subroutine mesh_free(self, stat)
    class(mm_mesh), intent(inout) :: self
    integer, intent(out), optional :: stat
    if (c_associated(self%h)) call mm_check(meshmove_mesh_free(self%h), "mesh_free", stat)
    self%h = c_null_ptr
  end subroutine

  integer(c_int32_t) function mesh_num_vertices(self) result(n)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t) :: nc
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes")
  end function

  integer(c_int32_t) function mesh_num_cells(self) result(nc)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t) :: n
    call mm_check(meshmove_mesh_sizes(self%h, n, nc), "mesh_sizes")
  end function

  !> Coordinates as xy(2, nv).
  subroutine mesh_coords(self, xy)
    class(mm_mesh), intent(in) :: self
    real(c_double), allocatable, intent(out) :: xy(:, :)
    allocate (xy(2, self%num_vertices()))
    call mm_check(meshmove_mesh_get_coords(self%h, int(size(xy), c_int32_t), xy), "mesh_get_coords")
  end subroutine

  !> Cells as c(3, nc), 1-based.
  subroutine mesh_cells(self, c)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: c(:, :)
    allocate (c(3, self%num_cells()))
    call mm_check(meshmove_mesh_get_cells(self%h, 1_c_int32_t, int(size(c), c_int32_t), c), "mesh_get_cells")
  end subroutine

  subroutine mesh_regions(self, r)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: r(:)
    allocate (r(self%num_cells()))
    call mm_check(meshmove_mesh_get_regions(self%h, int(size(r), c_int32_t), r), "mesh_get_regions")
  end subroutine

  !> Vertices (1-based) on a patch.
  subroutine mesh_patch_vertices(self, patch, v)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(in) :: patch
    integer(c_int32_t), allocatable, intent(out) :: v(:)
    integer(c_int32_t) :: buf(1), n, s
    s = meshmove_mesh_patch_vertices(self%h, patch, 1_c_int32_t, 0_c_int32_t, buf, n)
    if (s /= MESHMOVE_STATUS_OK .and. s /= MESHMOVE_STATUS_BUFFER_TOO_SMALL) call mm_check(s, "mesh_patch_vertices")
    allocate (v(n))
    call mm_check(meshmove_mesh_patch_vertices(self%h, patch, 1_c_int32_t, n, v, n), "mesh_patch_vertices")
  end subroutine

  subroutine bcs_create(self, stat)
    class(mm_bcs), intent(inout) :: self
    integer, intent(out), optional :: stat
    call mm_check(meshmove_bcs_create(self%h), "bcs_create", stat)
  end subroutine

  subroutine bcs_free(self, stat)
    class(mm_bcs), intent(inout) :: self
    integer, intent(out), optional :: stat
    if (c_associated(self%h)) call mm_check(meshmove_bcs_free(self%h), "bcs_free", stat)
    self%h = c_null_ptr
  end subroutine

  !> component 1 = x, 2 = y (Fortran numbering).
  subroutine bcs_set_kind(self, patch, component, kind, stat)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, component, kind
    integer, intent(out), optional :: stat
    call mm_check(meshmove_bcs_set_kind(self%h, patch, component - 1_c_int32_t, kind), "bcs_set_kind", stat)
  end subroutine

  subroutine bcs_set_kinds(self, patch, kind, stat)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, kind
    integer, intent(out), optional :: stat
    call mm_check(meshmove_bcs_set_kinds(self%h, patch, kind), "bcs_set_kinds", stat)
  end subroutine

  subroutine bcs_link_periodic(self, a, b, dx, dy, tol, stat)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: a, b
    real(c_double), intent(in) :: dx, dy, tol
    integer, intent(out), optional :: stat
    call mm_check(meshmove_bcs_link_periodic(self%h, a, b, dx, dy, tol), "bcs_link_periodic", stat)
  end subroutine

  subroutine bcs_set_interface(self, patch, variant, stat)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, variant
    integer, intent(out), optional :: stat
    call mm_check(meshmove_bcs_set_interface(self%h, patch, variant), "bcs_set_interface", stat)
  end subroutine

  subroutine solver_create(self, mesh, bcs, options, stat)
    class(mm_solver), intent(inout) :: self
    type(mm_mesh), intent(in) :: mesh
    type(mm_bcs), intent(in) :: bcs
    type(meshmove_options), intent(in), optional :: options
    integer, intent(out), optional :: stat
    type(meshmove_options) :: o
    integer(c_int32_t) :: s, levels
    if (present(options)) then
      o = options
    else
      o = mm_default_options()
    end if
    s = meshmove_solver_create(mesh%h, bcs%h, o, self%h)
    if (s == MESHMOVE_STATUS_OK) s = meshmove_solver_sizes(self%h, self%nv, levels)
    call mm_check(s, "solver_create", stat)
  end subroutine

  subroutine solver_free(self, stat)
    class(mm_solver), intent(inout) :: self
    integer, intent(out), optional :: stat
    if (c_associated(self%h)) call mm_check(meshmove_solver_free(self%h), "solver_free", stat)
    self%h = c_null_ptr
  end subroutine

  !> d(2, nv): prescribed displacement in, solution out.
  subroutine solver_solve(self, d, report, stat)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(inout) :: d(:, :)
    type(meshmove_report), intent(out), optional :: report
    integer, intent(out), optional :: stat
    type(meshmove_report) :: r
    real(c_double), allocatable :: p(:, :)
    allocate (p, source=d)
    call mm_check(meshmove_solver_solve(self%h, int(size(d), c_int32_t), p, c_null_ptr, d, r), "solver_solve", stat)
    if (present(report)) report = r
  end subroutine

  !> The drop-in call: xy(2, nv) updated in place from the boundary displacement bd(2, nv).
  subroutine solver_move(self, bd, xy, report, quality, stat)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in) :: bd(:, :)
    real(c_double), intent(inout) :: xy(:, :)
    type(meshmove_report), intent(out), optional :: report
    type(meshmove_quality), intent(out), optional :: quality
    integer, intent(out), optional :: stat
    type(meshmove_report) :: r
    type(meshmove_quality) :: q
    if (size(bd) /= size(xy)) then
      if (present(stat)) then
        stat = MESHMOVE_STATUS_INVALID_ARGUMENT
        return
      end if
      error stop "meshmove: solver_move: bd and xy differ in size"
    end if
    call mm_check(meshmove_solver_move(self%h, int(size(xy), c_int32_t), bd, xy, r, q), "solver_move", stat)
    if (present(report)) report = r
    if (present(quality)) quality = q
  end subroutine

  subroutine solver_move_in_steps(self, d, steps, stat)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in) :: d(:, :)
    integer(c_int32_t), intent(in) :: steps
    integer, intent(out), optional :: stat
    type(meshmove_report) :: r(steps)
    call mm_check(meshmove_solver_move_in_steps(self%h, int(size(d), c_int32_t), d, steps, steps, r), &
      "solver_move_in_steps", stat)
  end subroutine

  !> Writes the reference mesh moved by d(2, nv) (absent: the reference itself).
  subroutine solver_write_vtu(self, path, d, stat)
    class(mm_solver), intent(in) :: self
    character(*), intent(in) :: path
    real(c_double), intent(in), target, optional :: d(:, :)
    integer, intent(out), optional :: stat
    if (present(d)) then
      call mm_check(meshmove_solver_write_vtu(self%h, cstr(path), int(size(d), c_int32_t), c_loc(d)), &
        "solver_write_vtu", stat)
    else
      call mm_check(meshmove_solver_write_vtu(self%h, cstr(path), 0_c_int32_t, c_null_ptr), "solver_write_vtu", stat)
    end if
  end subroutine
end module meshmove
