! meshmove.f90: Fortran bindings of the meshmove C API (include/meshmove.h), shipped with the
! library. Two modules, as nlopt-f and fgsl do:
!   meshmove_c  raw bind(c) interfaces, one per C function, and named constants for the enums
!   meshmove    a thin handle layer wrapping every C function: derived types holding a private
!               c_ptr (mm_mesh, mm_bcs, mm_options, mm_solver), explicit create/free, 1-based
!               indices, offsets and components, coordinates and displacements as arrays of shape
!               (dim, number of vertices), arrays taken `contiguous` (a section is copied in and
!               out by the compiler, never passed as a bare address) and checked against the
!               sizes they are passed with, and optional `stat` and `errmsg` arguments on every
!               fallible routine; when `stat` is absent and the call fails, the routine stops with
!               the message (error stop).
! tests/fortran_interfaces.rs checks the interfaces, bind(c) types and constants against
! meshmove.h, and that the module `meshmove` calls every one of them; tests/fortran/bad_sizes.f90
! the size checks.
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
    MESHMOVE_STATUS_TANGLED = 13, MESHMOVE_STATUS_INVERTED = 14, MESHMOVE_STATUS_BUSY = 15, &
    MESHMOVE_STATUS_UNSUPPORTED = 16, MESHMOVE_STATUS_CANCELLED = 17, MESHMOVE_STATUS_CALLBACK_FAILED = 18, &
    MESHMOVE_STATUS_OUT_OF_MEMORY = 19
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
  integer(c_int32_t), parameter :: MESHMOVE_KIND_FIXED = 0, MESHMOVE_KIND_CLAMPED = 1, MESHMOVE_KIND_FREE = 2, &
    MESHMOVE_KIND_SLIP = 3
  integer(c_int32_t), parameter :: MESHMOVE_INTERFACE_SEPARATE = 0, MESHMOVE_INTERFACE_CONTINUOUS = 1
  ! meshmove_reference
  integer(c_int32_t), parameter :: MESHMOVE_REFERENCE_INCREMENTAL = 0, MESHMOVE_REFERENCE_ORIGINAL = 1
  ! meshmove_cell_type (VTK's cell type ids)
  integer(c_int32_t), parameter :: MESHMOVE_CELL_TYPE_TRIANGLE = 5, MESHMOVE_CELL_TYPE_QUAD = 9, &
    MESHMOVE_CELL_TYPE_TETRA = 10, MESHMOVE_CELL_TYPE_HEXAHEDRON = 12, MESHMOVE_CELL_TYPE_WEDGE = 13, &
    MESHMOVE_CELL_TYPE_PYRAMID = 14
  integer(c_int32_t), parameter :: MESHMOVE_VERSION_MAJOR = 0, MESHMOVE_VERSION_MINOR = 2, &
    MESHMOVE_VERSION_PATCH = 0

  type, bind(c) :: meshmove_report
    integer(c_int32_t) :: cycles
    real(c_double) :: max_correction, rel_residual, seconds
    integer(c_int32_t) :: converged
    real(c_double) :: max_slip_offwall
  end type
  type, bind(c) :: meshmove_quality
    integer(c_int32_t) :: inverted
    real(c_double) :: min_volume_ratio, max_volume_ratio, min_angle_deg
    integer(c_int32_t) :: negative_volume_cells
    real(c_double) :: min_corner_jacobian_ratio
  end type
  type, bind(c) :: meshmove_step_report
    integer(c_int32_t) :: step, substep
    real(c_double) :: fraction
    integer(c_int32_t) :: cycles
    real(c_double) :: rel_residual
    integer(c_int32_t) :: converged, rebuilt, inverted
    real(c_double) :: min_volume_ratio, min_angle_deg, seconds
    integer(c_int32_t) :: accepted
    real(c_double) :: max_slip_offwall
  end type
  type, bind(c) :: meshmove_step_seconds
    real(c_double) :: reference, solve, quality
  end type

  interface
    ! ---- errors and version
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
    ! ---- options
    integer(c_int32_t) function meshmove_options_create(out) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_options_free(options) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
    end function
    integer(c_int32_t) function meshmove_options_set_method(options, method) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: method
    end function
    integer(c_int32_t) function meshmove_options_set_mode(options, mode) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: mode
    end function
    integer(c_int32_t) function meshmove_options_set_criterion(options, criterion) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: criterion
    end function
    integer(c_int32_t) function meshmove_options_set_threads(options, threads) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: threads
    end function
    integer(c_int32_t) function meshmove_options_set_memory_budget(options, bytes) bind(c)
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int64_t), value :: bytes
    end function
    integer(c_int32_t) function meshmove_options_set_tol(options, tol) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: options
      real(c_double), value :: tol
    end function
    integer(c_int32_t) function meshmove_options_set_max_cycles(options, max_cycles) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: max_cycles
    end function
    integer(c_int32_t) function meshmove_options_set_cheb_degree(options, degree) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: degree
    end function
    integer(c_int32_t) function meshmove_options_set_cheb_coarse_degree(options, degree) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: degree
    end function
    integer(c_int32_t) function meshmove_options_set_cheb_lower_ratio(options, ratio) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: options
      real(c_double), value :: ratio
    end function
    integer(c_int32_t) function meshmove_options_set_substepping(options, max_substeps, min_volume_ratio) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: options
      integer(c_int32_t), value :: max_substeps
      real(c_double), value :: min_volume_ratio
    end function
    integer(c_int32_t) function meshmove_options_set_reference_mode(options, mode) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: options
      integer(c_int32_t), value :: mode
    end function
    ! ---- mesh
    integer(c_int32_t) function meshmove_mesh_create(dim, num_vertices, coords, num_cells, cell_offsets, &
        num_cell_vertices, cell_connectivity, cell_types, num_faces, face_offsets, num_face_vertices, &
        face_connectivity, face_patch, cell_region, index_base, out) bind(c)
      import :: c_int32_t, c_double, c_ptr
      integer(c_int32_t), value :: dim, num_vertices, num_cells, num_cell_vertices, num_faces, num_face_vertices, &
        index_base
      real(c_double), intent(in) :: coords(*)
      type(c_ptr), value :: cell_offsets, face_offsets, cell_region
      integer(c_int32_t), intent(in) :: cell_connectivity(*), cell_types(*), face_connectivity(*), face_patch(*)
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_mesh_create_from_faces(dim, num_vertices, coords, num_faces, face_offsets, &
        num_face_vertices, face_connectivity, face_owner, face_neighbour, face_patch, num_cells, cell_region, &
        index_base, out) bind(c)
      import :: c_int32_t, c_double, c_ptr
      integer(c_int32_t), value :: dim, num_vertices, num_faces, num_face_vertices, num_cells, index_base
      real(c_double), intent(in) :: coords(*)
      integer(c_int32_t), intent(in) :: face_offsets(*), face_connectivity(*), face_owner(*), face_neighbour(*), &
        face_patch(*)
      type(c_ptr), value :: cell_region
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_mesh_create_triangles(num_vertices, coords, num_cells, cells, index_base, &
        num_tagged, tagged_edges, tagged_patches, regions, out) bind(c)
      import :: c_int32_t, c_double, c_ptr
      integer(c_int32_t), value :: num_vertices, num_cells, index_base, num_tagged
      real(c_double), intent(in) :: coords(*)
      integer(c_int32_t), intent(in) :: cells(*), tagged_edges(*), tagged_patches(*)
      type(c_ptr), value :: regions
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
    integer(c_int32_t) function meshmove_mesh_sizes(mesh, dim, num_vertices, num_cells, num_cell_vertices, &
        num_faces, num_face_vertices) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), intent(out) :: dim, num_vertices, num_cells, num_cell_vertices, num_faces, &
        num_face_vertices
    end function
    integer(c_int32_t) function meshmove_mesh_get_coords(mesh, len, coords) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: len
      real(c_double), intent(out) :: coords(*)
    end function
    integer(c_int32_t) function meshmove_mesh_get_cells(mesh, index_base, num_offsets, offsets, num_connectivity, &
        connectivity, num_types, types) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: index_base, num_offsets, num_connectivity, num_types
      integer(c_int32_t), intent(out) :: offsets(*), connectivity(*), types(*)
    end function
    integer(c_int32_t) function meshmove_mesh_get_faces(mesh, index_base, num_offsets, offsets, num_connectivity, &
        connectivity, num_patches, patches) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: index_base, num_offsets, num_connectivity, num_patches
      integer(c_int32_t), intent(out) :: offsets(*), connectivity(*), patches(*)
    end function
    integer(c_int32_t) function meshmove_mesh_polyhedron_sizes(mesh, num_faces, num_face_vertices) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), intent(out) :: num_faces, num_face_vertices
    end function
    integer(c_int32_t) function meshmove_mesh_get_polyhedron_faces(mesh, index_base, num_cell_faces, cell_faces, &
        num_face_offsets, face_offsets, num_connectivity, connectivity) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), value :: index_base, num_cell_faces, num_face_offsets, num_connectivity
      integer(c_int32_t), intent(out) :: cell_faces(*), face_offsets(*), connectivity(*)
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
    ! ---- boundary conditions
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
    integer(c_int32_t) function meshmove_bcs_link_periodic(bcs, patch_a, patch_b, dim, offset, tol) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch_a, patch_b, dim
      real(c_double), intent(in) :: offset(*)
      real(c_double), value :: tol
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
    integer(c_int32_t) function meshmove_bcs_set_slip_surface(bcs, patch, closest, user_data) bind(c)
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch
      type(c_funptr), value :: closest
      type(c_ptr), value :: user_data
    end function
    integer(c_int32_t) function meshmove_bcs_set_slip_surface_checked(bcs, patch, closest, user_data) bind(c)
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: bcs
      integer(c_int32_t), value :: patch
      type(c_funptr), value :: closest
      type(c_ptr), value :: user_data
    end function
    ! ---- solver
    integer(c_int32_t) function meshmove_solver_create(mesh, bcs, options, out) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh, bcs, options
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_solver_free(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
    end function
    integer(c_int32_t) function meshmove_solver_sizes(solver, dim, num_vertices, num_levels) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
      integer(c_int32_t), intent(out) :: dim, num_vertices, num_levels
    end function
    integer(c_int32_t) function meshmove_solver_set_rigid_motion(solver, patch, translation, rotation, center) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: patch
      real(c_double), intent(in) :: translation(*), rotation(*), center(*)
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
    integer(c_int32_t) function meshmove_solver_step_seconds(solver, capacity, seconds, count) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver, seconds
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
    integer(c_int32_t) function meshmove_solver_set_progress(solver, progress, user_data) bind(c)
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: solver
      type(c_funptr), value :: progress
      type(c_ptr), value :: user_data
    end function
    integer(c_int32_t) function meshmove_solver_cancel(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
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
    integer(c_int32_t) function meshmove_solver_get_total_displacement(solver, len, displacement) bind(c)
      import :: c_int32_t, c_ptr, c_double
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len
      real(c_double), intent(out) :: displacement(*)
    end function
    integer(c_int32_t) function meshmove_solver_total_quality(solver, quality) bind(c)
      import :: c_int32_t, c_ptr, meshmove_quality
      type(c_ptr), value :: solver
      type(meshmove_quality), intent(out) :: quality
    end function
  end interface
end module meshmove_c


module meshmove
  use, intrinsic :: iso_c_binding
  use meshmove_c
  implicit none (type, external)
  private
  public :: meshmove_report, meshmove_quality, meshmove_step_report, meshmove_step_seconds, &
    mm_mesh, mm_bcs, mm_options, mm_solver, &
    mm_last_error, mm_last_error_message, mm_status_name, mm_version, mm_check
  ! the named constants of meshmove_c
  public :: MESHMOVE_STATUS_OK, MESHMOVE_STATUS_NULL_POINTER, MESHMOVE_STATUS_INVALID_HANDLE, &
    MESHMOVE_STATUS_INVALID_ARGUMENT, MESHMOVE_STATUS_INVALID_MESH, MESHMOVE_STATUS_INVALID_BCS, &
    MESHMOVE_STATUS_ILL_POSED, MESHMOVE_STATUS_COARSENING, MESHMOVE_STATUS_DIVERGED, MESHMOVE_STATUS_IO, &
    MESHMOVE_STATUS_BUFFER_TOO_SMALL, MESHMOVE_STATUS_PANIC, MESHMOVE_STATUS_NOT_CONVERGED, &
    MESHMOVE_STATUS_TANGLED, MESHMOVE_STATUS_INVERTED, MESHMOVE_STATUS_BUSY, MESHMOVE_STATUS_UNSUPPORTED, &
    MESHMOVE_STATUS_CANCELLED, MESHMOVE_STATUS_CALLBACK_FAILED, MESHMOVE_STATUS_OUT_OF_MEMORY, &
    MESHMOVE_MAX_STEPS, MESHMOVE_MAX_CYCLES, MESHMOVE_MAX_CHEB_DEGREE, MESHMOVE_MAX_THREADS, &
    MESHMOVE_MAX_SUBSTEPS, MESHMOVE_MAX_VERTICES, MESHMOVE_MAX_CELLS, MESHMOVE_METHOD_BIHARMONIC, &
    MESHMOVE_METHOD_LAPLACIAN, MESHMOVE_METHOD_SPRING, MESHMOVE_MODE_DEFAULT, MESHMOVE_MODE_PAPER_FAITHFUL, &
    MESHMOVE_CRITERION_RELATIVE_RESIDUAL, MESHMOVE_CRITERION_MAX_CORRECTION, MESHMOVE_KIND_FIXED, &
    MESHMOVE_KIND_CLAMPED, MESHMOVE_KIND_FREE, MESHMOVE_KIND_SLIP, MESHMOVE_INTERFACE_SEPARATE, MESHMOVE_INTERFACE_CONTINUOUS, &
    MESHMOVE_REFERENCE_INCREMENTAL, MESHMOVE_REFERENCE_ORIGINAL, MESHMOVE_CELL_TYPE_TRIANGLE, &
    MESHMOVE_CELL_TYPE_QUAD, MESHMOVE_CELL_TYPE_TETRA, MESHMOVE_CELL_TYPE_HEXAHEDRON, MESHMOVE_CELL_TYPE_WEDGE, &
    MESHMOVE_CELL_TYPE_PYRAMID, MESHMOVE_VERSION_MAJOR, MESHMOVE_VERSION_MINOR, MESHMOVE_VERSION_PATCH

  !> A mesh. Vertex indices in and out are 1-based, and so are CSR offsets (offsets(1) = 1).
  type :: mm_mesh
    private
    type(c_ptr) :: h = c_null_ptr
  contains
    procedure :: create => mesh_create
    procedure :: create_triangles => mesh_create_triangles
    procedure :: create_from_faces => mesh_create_from_faces
    procedure :: read_msh => mesh_read_msh
    procedure :: free => mesh_free
    procedure :: sizes => mesh_sizes
    procedure :: dim => mesh_dim
    procedure :: num_vertices => mesh_num_vertices
    procedure :: num_cells => mesh_num_cells
    procedure :: coords => mesh_coords
    procedure :: cells => mesh_cells
    procedure :: faces => mesh_faces
    procedure :: polyhedron_faces => mesh_polyhedron_faces
    procedure :: regions => mesh_regions
    procedure :: patch_vertices => mesh_patch_vertices
    procedure :: write_vtu => mesh_write_vtu
  end type

  !> Boundary conditions. Components are 1 = x, 2 = y, 3 = z.
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
    procedure :: set_slip_surface => bcs_set_slip_surface
    procedure :: set_slip_surface_checked => bcs_set_slip_surface_checked
  end type

  !> Solver options: create (the defaults), set what you need, pass to mm_solver%create, free.
  type :: mm_options
    private
    type(c_ptr) :: h = c_null_ptr
  contains
    procedure :: create => options_create
    procedure :: free => options_free
    procedure :: set_method => options_set_method
    procedure :: set_mode => options_set_mode
    procedure :: set_criterion => options_set_criterion
    procedure :: set_threads => options_set_threads
    procedure :: set_memory_budget => options_set_memory_budget
    procedure :: set_tol => options_set_tol
    procedure :: set_max_cycles => options_set_max_cycles
    procedure :: set_cheb_degree => options_set_cheb_degree
    procedure :: set_cheb_coarse_degree => options_set_cheb_coarse_degree
    procedure :: set_cheb_lower_ratio => options_set_cheb_lower_ratio
    procedure :: set_substepping => options_set_substepping
    procedure :: set_reference_mode => options_set_reference_mode
  end type

  !> A solver. Coordinates and displacements are arrays of shape (dim, number of vertices).
  type :: mm_solver
    private
    type(c_ptr) :: h = c_null_ptr
    integer(c_int32_t) :: nd = 0, nv = 0
  contains
    procedure :: create => solver_create
    procedure :: free => solver_free
    procedure :: dim => solver_dim
    procedure :: num_vertices => solver_num_vertices
    procedure :: num_levels => solver_num_levels
    procedure :: set_rigid_motion => solver_set_rigid_motion
    procedure :: clear_rigid_motions => solver_clear_rigid_motions
    procedure :: solve => solver_solve
    procedure :: cycle => solver_cycle
    procedure :: move => solver_move
    procedure :: move_in_steps => solver_move_in_steps
    procedure :: step_reports => solver_step_reports
    procedure :: step_seconds => solver_step_seconds
    procedure :: set_reference => solver_set_reference
    procedure :: set_substepping => solver_set_substepping
    procedure :: set_reference_mode => solver_set_reference_mode
    procedure :: set_progress => solver_set_progress
    procedure :: cancel => solver_cancel
    procedure :: coords => solver_coords
    procedure :: displacement => solver_displacement
    procedure :: quality => solver_quality
    procedure :: write_vtu => solver_write_vtu
    procedure :: get_total_displacement => solver_total_displacement
    procedure :: total_quality => solver_total_quality
  end type

  !> The message of the last failure found by this module itself (a size it checked), until the
  !> next library call; mm_last_error returns it first. Shared by the threads of a program: with
  !> threads, ask for `errmsg` instead.
  character(len=:), allocatable :: f_msg

contains

  ! ---- errors, version ---------------------------------------------------------------------

  !> A NUL-terminated C string (static or the library's thread-local message) as a Fortran one.
  function c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    n = 0
    if (c_associated(p)) then
      call c_f_pointer(p, chars, [huge(0)])
      do while (chars(n + 1) /= c_null_char)
        n = n + 1
      end do
    end if
    allocate (character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function

  !> The message of the last failed call on this thread (or of the last size this module refused).
  function mm_last_error() result(msg)
    character(len=:), allocatable :: msg
    if (allocated(f_msg)) then
      msg = f_msg
    else
      msg = c_string(meshmove_last_error())
    end if
  end function

  !> The library's last error message into a fixed-length `buf` (blank-padded); `stat` is
  !> MESHMOVE_STATUS_BUFFER_TOO_SMALL when it was cut (never an error stop).
  subroutine mm_last_error_message(buf, stat)
    character(*), intent(out) :: buf
    integer(c_int32_t), intent(out), optional :: stat
    character(kind=c_char) :: c(len(buf) + 1)
    integer(c_size_t) :: needed
    integer(c_int32_t) :: s
    integer :: i
    s = meshmove_last_error_message(c, int(size(c), c_size_t), needed)
    buf = ""
    do i = 1, len(buf)
      if (c(i) == c_null_char) exit
      buf(i:i) = c(i)
    end do
    if (present(stat)) stat = s
  end subroutine

  !> The name of a status value, e.g. "MESHMOVE_STATUS_INVALID_MESH".
  function mm_status_name(s) result(name)
    integer, intent(in) :: s
    character(len=:), allocatable :: name
    name = c_string(meshmove_status_name(int(s, c_int32_t)))
  end function

  !> The library's version (compare with MESHMOVE_VERSION_MAJOR and _MINOR).
  subroutine mm_version(major, minor, patch, stat, errmsg)
    integer(c_int32_t), intent(out) :: major, minor, patch
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_version(major, minor, patch), "version", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Stores status `s` in `stat` (and the message in `errmsg`) when present; otherwise stops with
  !> the message if `s` is not OK.
  subroutine mm_check(s, where, stat, errmsg)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: where
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(s, where, stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  ! An optional deferred-length `errmsg` is only ever assigned in the routine whose dummy it is
  ! (`if (present(errmsg)) call message(errmsg)`), never passed on to another optional dummy:
  ! gfortran (12 at least) passes on a copy of its length there, and the caller would see the
  ! new text with the old length.

  !> Stores status `s` in `stat` when present; otherwise stops with the message if `s` is not OK.
  subroutine check(s, where, stat)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: where
    integer(c_int32_t), intent(out), optional :: stat
    if (allocated(f_msg)) deallocate (f_msg)
    if (present(stat)) then
      stat = s
    else if (s /= MESHMOVE_STATUS_OK) then
      error stop "meshmove: " // where // ": " // mm_last_error()
    end if
  end subroutine

  !> The message of the call just checked: "" after a success (the library clears its message).
  subroutine message(errmsg)
    character(len=:), allocatable, intent(out) :: errmsg
    errmsg = mm_last_error()
  end subroutine

  !> A failure found by this module before calling the library (status `s`, message `text`).
  subroutine fail(s, where, text, stat)
    integer(c_int32_t), intent(in) :: s
    character(*), intent(in) :: where, text
    integer(c_int32_t), intent(out), optional :: stat
    f_msg = "meshmove_" // where // ": " // text
    if (present(stat)) then
      stat = s
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

  !> True (after `fail`) unless `a` has shape (nd, nv); nd 0 is a handle never created.
  logical function bad_shape(a1, a2, nd, nv, what, where, stat) result(bad)
    integer, intent(in) :: a1, a2
    integer(c_int32_t), intent(in) :: nd, nv
    character(*), intent(in) :: what, where
    integer(c_int32_t), intent(out), optional :: stat
    if (nd == 0) then
      ! No dimension: the handle was never created (or its create failed).
      bad = .true.
      call fail(MESHMOVE_STATUS_NULL_POINTER, where, "the handle was never created (or its create failed): " // &
        "create it first", stat)
      return
    end if
    bad = a1 /= nd .or. a2 /= nv
    if (bad) call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, where, what // " has shape (" // str(a1) // ", " // &
      str(a2) // "); the mesh has " // str(int(nv)) // " vertices in " // str(int(nd)) // "D, so (" // &
      str(int(nd)) // ", " // str(int(nv)) // ") is needed", stat)
  end function

  !> True (after `fail`) unless size `n` of `what` is `want`.
  logical function bad_size(n, want, what, where, stat) result(bad)
    integer, intent(in) :: n, want
    character(*), intent(in) :: what, where
    integer(c_int32_t), intent(out), optional :: stat
    bad = n /= want
    if (bad) call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, where, what // " has " // str(n) // &
      " entries; " // str(want) // " are needed", stat)
  end function

  function cstr(s) result(c)
    character(*), intent(in) :: s
    character(kind=c_char, len=len_trim(s) + 1) :: c
    c = trim(s) // c_null_char
  end function

  ! ---- options -------------------------------------------------------------------------------

  subroutine options_create(self, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_create(self%h), "options_create", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_free(self, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (present(errmsg)) errmsg = ""
    if (c_associated(self%h)) then
      call check(meshmove_options_free(self%h), "options_free", stat)
      if (present(errmsg)) call message(errmsg)
    end if
    self%h = c_null_ptr
  end subroutine

  !> MESHMOVE_METHOD_BIHARMONIC (default), _LAPLACIAN or _SPRING.
  subroutine options_set_method(self, method, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: method
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_method(self%h, method), "options_set_method", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> MESHMOVE_MODE_DEFAULT or _PAPER_FAITHFUL.
  subroutine options_set_mode(self, mode, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: mode
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_mode(self%h, mode), "options_set_mode", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> MESHMOVE_CRITERION_RELATIVE_RESIDUAL (default) or _MAX_CORRECTION.
  subroutine options_set_criterion(self, criterion, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: criterion
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_criterion(self%h, criterion), "options_set_criterion", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Worker threads of the solver (0: one per core; 1 for an MPI rank per core).
  subroutine options_set_threads(self, threads, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: threads
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_threads(self%h, threads), "options_set_threads", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Most memory a solver made with these options may take, in bytes (0: no limit): a larger
  !> estimated need fails solver%create with MESHMOVE_STATUS_OUT_OF_MEMORY before any build.
  subroutine options_set_memory_budget(self, bytes, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int64_t), intent(in) :: bytes
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_memory_budget(self%h, bytes), "options_set_memory_budget", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_tol(self, tol, stat, errmsg)
    class(mm_options), intent(inout) :: self
    real(c_double), intent(in) :: tol
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_tol(self%h, tol), "options_set_tol", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_max_cycles(self, max_cycles, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: max_cycles
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_max_cycles(self%h, max_cycles), "options_set_max_cycles", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_cheb_degree(self, degree, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: degree
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_cheb_degree(self%h, degree), "options_set_cheb_degree", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_cheb_coarse_degree(self, degree, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: degree
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_cheb_coarse_degree(self%h, degree), "options_set_cheb_coarse_degree", &
      stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_cheb_lower_ratio(self, ratio, stat, errmsg)
    class(mm_options), intent(inout) :: self
    real(c_double), intent(in) :: ratio
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_cheb_lower_ratio(self%h, ratio), "options_set_cheb_lower_ratio", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_substepping(self, max_substeps, min_volume_ratio, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: max_substeps
    real(c_double), intent(in) :: min_volume_ratio
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_substepping(self%h, max_substeps, min_volume_ratio), &
      "options_set_substepping", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine options_set_reference_mode(self, mode, stat, errmsg)
    class(mm_options), intent(inout) :: self
    integer(c_int32_t), intent(in) :: mode
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_options_set_reference_mode(self%h, mode), "options_set_reference_mode", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  ! ---- mesh ----------------------------------------------------------------------------------

  !> A mesh of any dimension and cell types: coords(dim, nv); cell_types(nc), MESHMOVE_CELL_TYPE_*
  !> values; connectivity: the cells' corners one after the other, 1-based, in VTK's order for
  !> each type; cell_offsets(nc + 1), optional: where each cell starts in connectivity, from 1 to
  !> size(connectivity) + 1 (absent: each cell has the corners of its type). Tagged faces,
  !> optional: face_connectivity (1-based) with face_patch(nf) and face_offsets(nf + 1) as
  !> cell_offsets (absent: dim vertices per face). regions(nc), optional.
  subroutine mesh_create(self, coords, cell_types, connectivity, face_connectivity, face_patch, cell_offsets, &
      face_offsets, regions, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    real(c_double), intent(in), contiguous :: coords(:, :)
    integer(c_int32_t), intent(in), contiguous :: cell_types(:), connectivity(:)
    integer(c_int32_t), intent(in), contiguous, optional :: face_connectivity(:), face_patch(:), cell_offsets(:), &
      face_offsets(:)
    integer(c_int32_t), intent(in), contiguous, target, optional :: regions(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    character(*), parameter :: w = "mesh_create"
    integer(c_int32_t), allocatable, target :: co(:), fo(:)
    integer(c_int32_t), allocatable :: fc(:), fp(:)
    type(c_ptr) :: cop, fop, rp
    integer :: nc
    cop = c_null_ptr
    fop = c_null_ptr
    rp = c_null_ptr
    nc = size(cell_types)
    if (present(face_connectivity) .neqv. present(face_patch)) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "face_connectivity and face_patch go together", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (size(coords, 2) > MESHMOVE_MAX_VERTICES .or. nc > MESHMOVE_MAX_CELLS) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "more than MESHMOVE_MAX_VERTICES vertices or " // &
        "MESHMOVE_MAX_CELLS cells", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (present(face_connectivity)) then
      allocate (fc, source=face_connectivity)
      allocate (fp, source=face_patch)
    else
      allocate (fc(0), fp(0))
    end if
    if (present(cell_offsets)) then
      if (bad_size(size(cell_offsets), nc + 1, "cell_offsets (number of cells + 1)", w, stat)) then
        if (present(errmsg)) call message(errmsg)
        return
      end if
      allocate (co, source=cell_offsets - 1_c_int32_t)
      cop = c_loc(co)
    end if
    if (present(face_offsets)) then
      if (bad_size(size(face_offsets), size(fp) + 1, "face_offsets (number of faces + 1)", w, stat)) then
        if (present(errmsg)) call message(errmsg)
        return
      end if
      allocate (fo, source=face_offsets - 1_c_int32_t)
      fop = c_loc(fo)
    end if
    if (present(regions)) then
      if (bad_size(size(regions), nc, "regions (one per cell)", w, stat)) then
        if (present(errmsg)) call message(errmsg)
        return
      end if
      if (nc > 0) rp = c_loc(regions)
    end if
    call check(meshmove_mesh_create(int(size(coords, 1), c_int32_t), int(size(coords, 2), c_int32_t), coords, &
      int(nc, c_int32_t), cop, int(size(connectivity), c_int32_t), connectivity, cell_types, &
      int(size(fp), c_int32_t), fop, int(size(fc), c_int32_t), fc, fp, rp, 1_c_int32_t, self%h), w, stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> A 2D triangle mesh: coords(2, nv); cells(3, nc) 1-based; tagged(2, nt) 1-based with
  !> patches(nt); regions(nc) optional.
  subroutine mesh_create_triangles(self, coords, cells, tagged, patches, regions, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    real(c_double), intent(in), contiguous :: coords(:, :)
    integer(c_int32_t), intent(in), contiguous :: cells(:, :), tagged(:, :), patches(:)
    integer(c_int32_t), intent(in), contiguous, target, optional :: regions(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    character(*), parameter :: w = "mesh_create_triangles"
    type(c_ptr) :: r
    r = c_null_ptr
    if (size(coords, 1) /= 2) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "coords has " // str(size(coords, 1)) // &
        " rows; it must be coords(2, number of vertices)", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (size(cells, 1) /= 3) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "cells has " // str(size(cells, 1)) // &
        " rows; it must be cells(3, number of cells)", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (size(tagged, 1) /= 2 .or. size(tagged, 2) /= size(patches)) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "tagged has shape (" // str(size(tagged, 1)) // ", " // &
        str(size(tagged, 2)) // ") and patches has " // str(size(patches)) // &
        " entries; tagged(2, n) needs patches(n)", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (size(coords, 2) > MESHMOVE_MAX_VERTICES .or. size(cells, 2) > MESHMOVE_MAX_CELLS) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "more than MESHMOVE_MAX_VERTICES vertices or " // &
        "MESHMOVE_MAX_CELLS cells", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (present(regions)) then
      if (size(regions) /= size(cells, 2)) then
        call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "regions has " // str(size(regions)) // &
          " entries; there are " // str(size(cells, 2)) // " cells", stat)
        if (present(errmsg)) call message(errmsg)
        return
      end if
      if (size(regions) > 0) r = c_loc(regions)
    end if
    call check(meshmove_mesh_create_triangles(int(size(coords, 2), c_int32_t), coords, &
      int(size(cells, 2), c_int32_t), cells, 1_c_int32_t, int(size(patches), c_int32_t), tagged, patches, r, &
      self%h), w, stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> A mesh from its faces, as finite-volume codes store it (OpenFOAM, code_saturne): coords(dim, nv); face f's
  !> vertices are face_vertices(face_offsets(f) : face_offsets(f + 1) - 1) (offsets and vertices 1-based), a loop
  !> whose right-hand normal points out of cell owner(f) into cell neighbour(f) (0 on the boundary); patch(f) >= 0
  !> on every boundary face, -1 on an untagged interior face; cells 1 to num_cells; regions(num_cells) optional.
  !> Tetrahedra, hexahedra, wedges and pyramids (triangles, quads in 2D) are recognised, other cells are polyhedra.
  subroutine mesh_create_from_faces(self, coords, face_offsets, face_vertices, owner, neighbour, patch, num_cells, &
      regions, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    real(c_double), intent(in), contiguous :: coords(:, :)
    integer(c_int32_t), intent(in), contiguous :: face_offsets(:), face_vertices(:), owner(:), neighbour(:), patch(:)
    integer(c_int32_t), intent(in) :: num_cells
    integer(c_int32_t), intent(in), contiguous, target, optional :: regions(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    character(*), parameter :: w = "mesh_create_from_faces"
    integer(c_int32_t), allocatable :: fo(:)
    type(c_ptr) :: r
    integer :: nf
    r = c_null_ptr
    nf = size(owner)
    if (size(face_offsets) /= nf + 1 .or. size(neighbour) /= nf .or. size(patch) /= nf) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "owner has " // str(nf) // " entries (one per face): " // &
        "face_offsets needs one more, neighbour and patch as many", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (size(coords, 2) > MESHMOVE_MAX_VERTICES .or. nf > MESHMOVE_MAX_VERTICES) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "more than MESHMOVE_MAX_VERTICES vertices or faces", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (present(regions)) then
      if (size(regions) /= num_cells) then
        call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, w, "regions has " // str(size(regions)) // &
          " entries; there are " // str(int(num_cells)) // " cells", stat)
        if (present(errmsg)) call message(errmsg)
        return
      end if
      if (size(regions) > 0) r = c_loc(regions)
    end if
    allocate (fo, source=face_offsets - 1_c_int32_t)
    call check(meshmove_mesh_create_from_faces(int(size(coords, 1), c_int32_t), int(size(coords, 2), c_int32_t), &
      coords, int(nf, c_int32_t), fo, int(size(face_vertices), c_int32_t), face_vertices, owner, neighbour, patch, &
      num_cells, r, 1_c_int32_t, self%h), w, stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Reads a Gmsh .msh file (physical groups of lines are patches, of triangles regions).
  subroutine mesh_read_msh(self, path, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    character(*), intent(in) :: path
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_mesh_read_msh(cstr(path), self%h), "mesh_read_msh", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine mesh_free(self, stat, errmsg)
    class(mm_mesh), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (present(errmsg)) errmsg = ""
    if (c_associated(self%h)) then
      call check(meshmove_mesh_free(self%h), "mesh_free", stat)
      if (present(errmsg)) call message(errmsg)
    end if
    self%h = c_null_ptr
  end subroutine

  !> Any of the sizes: the dimension, vertices, cells, cell connectivity length, faces (every
  !> boundary and interface face) and face connectivity length.
  subroutine mesh_sizes(self, dim, num_vertices, num_cells, num_cell_vertices, num_faces, num_face_vertices, &
      stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(out), optional :: dim, num_vertices, num_cells, num_cell_vertices, num_faces, &
      num_face_vertices
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n(6)
    n = 0
    call check(meshmove_mesh_sizes(self%h, n(1), n(2), n(3), n(4), n(5), n(6)), "mesh_sizes", stat)
    if (present(errmsg)) call message(errmsg)
    if (present(dim)) dim = n(1)
    if (present(num_vertices)) num_vertices = n(2)
    if (present(num_cells)) num_cells = n(3)
    if (present(num_cell_vertices)) num_cell_vertices = n(4)
    if (present(num_faces)) num_faces = n(5)
    if (present(num_face_vertices)) num_face_vertices = n(6)
  end subroutine

  integer(c_int32_t) function mesh_dim(self, stat, errmsg) result(d)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    d = 0
    call self%sizes(dim=d, stat=stat)
    if (present(errmsg)) call message(errmsg)
  end function

  integer(c_int32_t) function mesh_num_vertices(self, stat, errmsg) result(n)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    n = 0
    call self%sizes(num_vertices=n, stat=stat)
    if (present(errmsg)) call message(errmsg)
  end function

  integer(c_int32_t) function mesh_num_cells(self, stat, errmsg) result(n)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    n = 0
    call self%sizes(num_cells=n, stat=stat)
    if (present(errmsg)) call message(errmsg)
  end function

  !> Coordinates as xy(dim, nv).
  subroutine mesh_coords(self, xy, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    real(c_double), allocatable, intent(out) :: xy(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: d, n
    integer(c_int32_t) :: s
    d = 0
    n = 0
    call self%sizes(dim=d, num_vertices=n, stat=s)
    allocate (xy(d, n))
    if (s /= MESHMOVE_STATUS_OK) then
      call check(int(s, c_int32_t), "mesh_sizes", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_mesh_get_coords(self%h, int(size(xy), c_int32_t), xy), "mesh_get_coords", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The cells: types(nc) (MESHMOVE_CELL_TYPE_*), connectivity (1-based) and offsets(nc + 1)
  !> (1-based: cell c is connectivity(offsets(c) : offsets(c + 1) - 1)).
  subroutine mesh_cells(self, types, connectivity, offsets, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: types(:), connectivity(:)
    integer(c_int32_t), allocatable, intent(out), optional :: offsets(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: nc, ncv
    integer(c_int32_t), allocatable :: o(:)
    integer(c_int32_t) :: s
    nc = 0
    ncv = 0
    call self%sizes(num_cells=nc, num_cell_vertices=ncv, stat=s)
    allocate (types(nc), connectivity(ncv), o(nc + 1))
    if (s == MESHMOVE_STATUS_OK) s = meshmove_mesh_get_cells(self%h, 1_c_int32_t, nc + 1_c_int32_t, o, ncv, &
      connectivity, nc, types)
    call check(int(s, c_int32_t), "mesh_get_cells", stat)
    if (present(errmsg)) call message(errmsg)
    if (present(offsets)) offsets = o + 1_c_int32_t
  end subroutine

  !> The faces of the polyhedral cells (mesh%cells gives a polyhedron's corners): cell c's faces are
  !> cell_faces(c) : cell_faces(c + 1) - 1 (none for a cell of another type), face f's vertices
  !> connectivity(face_offsets(f) : face_offsets(f + 1) - 1), a loop whose normal points out of the cell
  !> (all 1-based).
  subroutine mesh_polyhedron_faces(self, cell_faces, face_offsets, connectivity, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: cell_faces(:), face_offsets(:), connectivity(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: nc, nf, nfv, s
    nc = 0
    nf = 0
    nfv = 0
    call self%sizes(num_cells=nc, stat=s)
    if (s == MESHMOVE_STATUS_OK) s = meshmove_mesh_polyhedron_sizes(self%h, nf, nfv)
    allocate (cell_faces(nc + 1), face_offsets(nf + 1), connectivity(nfv))
    if (s == MESHMOVE_STATUS_OK) s = meshmove_mesh_get_polyhedron_faces(self%h, 1_c_int32_t, nc + 1_c_int32_t, &
      cell_faces, nf + 1_c_int32_t, face_offsets, nfv, connectivity)
    call check(int(s, c_int32_t), "mesh_polyhedron_faces", stat)
    if (present(errmsg)) call message(errmsg)
    cell_faces = cell_faces + 1_c_int32_t
    face_offsets = face_offsets + 1_c_int32_t
  end subroutine

  !> The faces on patches (every boundary face, untagged ones on patch 0, and every tagged
  !> interior face): patches(nf), connectivity (1-based) and offsets(nf + 1) (1-based).
  subroutine mesh_faces(self, patches, connectivity, offsets, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: patches(:), connectivity(:)
    integer(c_int32_t), allocatable, intent(out), optional :: offsets(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: nf, nfv
    integer(c_int32_t), allocatable :: o(:)
    integer(c_int32_t) :: s
    nf = 0
    nfv = 0
    call self%sizes(num_faces=nf, num_face_vertices=nfv, stat=s)
    allocate (patches(nf), connectivity(nfv), o(nf + 1))
    if (s == MESHMOVE_STATUS_OK) s = meshmove_mesh_get_faces(self%h, 1_c_int32_t, nf + 1_c_int32_t, o, nfv, &
      connectivity, nf, patches)
    call check(int(s, c_int32_t), "mesh_get_faces", stat)
    if (present(errmsg)) call message(errmsg)
    if (present(offsets)) offsets = o + 1_c_int32_t
  end subroutine

  subroutine mesh_regions(self, r, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), allocatable, intent(out) :: r(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: nc
    integer(c_int32_t) :: s
    nc = 0
    call self%sizes(num_cells=nc, stat=s)
    allocate (r(nc))
    if (s == MESHMOVE_STATUS_OK) s = meshmove_mesh_get_regions(self%h, int(size(r), c_int32_t), r)
    call check(int(s, c_int32_t), "mesh_get_regions", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Vertices (1-based) on a patch.
  subroutine mesh_patch_vertices(self, patch, v, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    integer(c_int32_t), intent(in) :: patch
    integer(c_int32_t), allocatable, intent(out) :: v(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: buf(1), n, cap, s
    n = 0
    s = meshmove_mesh_patch_vertices(self%h, patch, 1_c_int32_t, 0_c_int32_t, buf, n)
    if (s /= MESHMOVE_STATUS_OK .and. s /= MESHMOVE_STATUS_BUFFER_TOO_SMALL) then
      allocate (v(0))
      call check(s, "mesh_patch_vertices", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    cap = n
    allocate (v(max(cap, 1_c_int32_t)))
    call check(meshmove_mesh_patch_vertices(self%h, patch, 1_c_int32_t, cap, v, n), "mesh_patch_vertices", &
      stat)
    if (present(errmsg)) call message(errmsg)
    if (size(v) /= n) v = v(1:n)
  end subroutine

  !> Writes the mesh moved by d(dim, nv) (absent: the mesh itself) as a .vtu file.
  subroutine mesh_write_vtu(self, path, d, stat, errmsg)
    class(mm_mesh), intent(in) :: self
    character(*), intent(in) :: path
    real(c_double), intent(in), contiguous, target, optional :: d(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: nd, n
    integer(c_int32_t) :: s
    if (present(d)) then
      nd = 0
      n = 0
      call self%sizes(dim=nd, num_vertices=n, stat=s)
      if (s /= MESHMOVE_STATUS_OK) then
        call check(int(s, c_int32_t), "mesh_sizes", stat)
        if (present(errmsg)) call message(errmsg)
        return
      end if
      if (bad_shape(size(d, 1), size(d, 2), nd, n, "d", "mesh_write_vtu", stat)) then
        if (present(errmsg)) call message(errmsg)
        return
      end if
      call check(meshmove_mesh_write_vtu(self%h, cstr(path), int(size(d), c_int32_t), c_loc(d)), &
        "mesh_write_vtu", stat)
      if (present(errmsg)) call message(errmsg)
    else
      call check(meshmove_mesh_write_vtu(self%h, cstr(path), 0_c_int32_t, c_null_ptr), "mesh_write_vtu", stat)
      if (present(errmsg)) call message(errmsg)
    end if
  end subroutine

  ! ---- boundary conditions -------------------------------------------------------------------

  subroutine bcs_create(self, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_bcs_create(self%h), "bcs_create", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine bcs_free(self, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (present(errmsg)) errmsg = ""
    if (c_associated(self%h)) then
      call check(meshmove_bcs_free(self%h), "bcs_free", stat)
      if (present(errmsg)) call message(errmsg)
    end if
    self%h = c_null_ptr
  end subroutine

  !> component 1 = x, 2 = y, 3 = z (Fortran numbering).
  subroutine bcs_set_kind(self, patch, component, kind, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, component, kind
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (component < 1 .or. component > 3) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, "bcs_set_kind", "component " // str(int(component)) // &
        " does not exist (1 = x, 2 = y, 3 = z)", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_bcs_set_kind(self%h, patch, component - 1_c_int32_t, kind), "bcs_set_kind", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine bcs_set_kinds(self, patch, kind, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, kind
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_bcs_set_kinds(self%h, patch, kind), "bcs_set_kinds", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine bcs_set_default_kind(self, kind, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: kind
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_bcs_set_default_kind(self%h, kind), "bcs_set_default_kind", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Every vertex v of patch a is joined to the vertex of patch b at v + offset (offset(dim)).
  subroutine bcs_link_periodic(self, a, b, offset, tol, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: a, b
    real(c_double), intent(in), contiguous :: offset(:)
    real(c_double), intent(in) :: tol
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_bcs_link_periodic(self%h, a, b, int(size(offset), c_int32_t), offset, tol), &
      "bcs_link_periodic", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> pairs(2, n): 1-based vertex pairs that become one unknown.
  subroutine bcs_link_pairs(self, pairs, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in), contiguous :: pairs(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (size(pairs, 1) /= 2) then
      call fail(MESHMOVE_STATUS_INVALID_ARGUMENT, "bcs_link_pairs", "pairs has " // str(size(pairs, 1)) // &
        " rows; it must be pairs(2, number of pairs)", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_bcs_link_pairs(self%h, int(size(pairs, 2), c_int32_t), pairs, 1_c_int32_t), &
      "bcs_link_pairs", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine bcs_set_interface(self, patch, variant, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch, variant
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_bcs_set_interface(self%h, patch, variant), "bcs_set_interface", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The analytic shape of SLIP patch `patch`: `closest = c_funloc(f)` of a bind(c) subroutine
  !> f(user_data, dim, x, out) with `type(c_ptr), value :: user_data`, `integer(c_int32_t), value
  !> :: dim`, `real(c_double), intent(in) :: x(dim)`, `real(c_double), intent(out) :: out(dim)`
  !> that writes the wall's closest point to x; `c_null_funptr` removes it. `user_data` (default
  !> c_null_ptr) is handed back to f. The shape is where the wall is in the mesh a solver is made
  !> with; a wall moved rigidly carries it along (f is asked in the wall's original frame).
  subroutine bcs_set_slip_surface(self, patch, closest, user_data, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch
    type(c_funptr), intent(in) :: closest
    type(c_ptr), intent(in), optional :: user_data
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(c_ptr) :: ud
    ud = c_null_ptr
    if (present(user_data)) ud = user_data
    call check(meshmove_bcs_set_slip_surface(self%h, patch, closest, ud), "bcs_set_slip_surface", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> As set_slip_surface, with f an integer(c_int32_t) bind(c) function of the same arguments
  !> returning 0 on success and anything else on failure: the solver call that asked then fails
  !> with MESHMOVE_STATUS_CALLBACK_FAILED and changes nothing. f runs on the solver's worker
  !> threads and must return normally (never stop, error stop or jump out of it).
  subroutine bcs_set_slip_surface_checked(self, patch, closest, user_data, stat, errmsg)
    class(mm_bcs), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch
    type(c_funptr), intent(in) :: closest
    type(c_ptr), intent(in), optional :: user_data
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(c_ptr) :: ud
    ud = c_null_ptr
    if (present(user_data)) ud = user_data
    call check(meshmove_bcs_set_slip_surface_checked(self%h, patch, closest, ud), "bcs_set_slip_surface_checked", &
      stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  ! ---- solver --------------------------------------------------------------------------------

  !> A solver for mesh and bcs with options (absent: the defaults).
  subroutine solver_create(self, mesh, bcs, options, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    type(mm_mesh), intent(in) :: mesh
    type(mm_bcs), intent(in) :: bcs
    type(mm_options), intent(in), optional :: options
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(c_ptr) :: o
    integer(c_int32_t) :: s, levels
    o = c_null_ptr
    if (present(options)) o = options%h
    s = meshmove_solver_create(mesh%h, bcs%h, o, self%h)
    if (s == MESHMOVE_STATUS_OK) s = meshmove_solver_sizes(self%h, self%nd, self%nv, levels)
    call check(s, "solver_create", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine solver_free(self, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(stat)) stat = MESHMOVE_STATUS_OK
    if (present(errmsg)) errmsg = ""
    if (c_associated(self%h)) then
      call check(meshmove_solver_free(self%h), "solver_free", stat)
      if (present(errmsg)) call message(errmsg)
    end if
    self%h = c_null_ptr
    self%nd = 0
    self%nv = 0
  end subroutine

  integer(c_int32_t) function solver_dim(self) result(d)
    class(mm_solver), intent(in) :: self
    d = self%nd
  end function

  integer(c_int32_t) function solver_num_vertices(self) result(n)
    class(mm_solver), intent(in) :: self
    n = self%nv
  end function

  integer(c_int32_t) function solver_num_levels(self, stat, errmsg) result(levels)
    class(mm_solver), intent(in) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: d, n
    d = 0
    n = 0
    levels = 0
    call check(meshmove_solver_sizes(self%h, d, n, levels), "solver_sizes", stat)
    if (present(errmsg)) call message(errmsg)
  end function

  !> Patch `patch` moves rigidly: rotation about center(dim), then translation(dim); rotation
  !> holds the angle (radians) in 2D, the rotation vector (axis times angle) in 3D.
  subroutine solver_set_rigid_motion(self, patch, translation, rotation, center, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(in) :: patch
    real(c_double), intent(in), contiguous :: translation(:), rotation(:), center(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    character(*), parameter :: w = "solver_set_rigid_motion"
    if (bad_size(size(translation), int(self%nd), "translation (one per dimension)", w, stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (bad_size(size(rotation), merge(1, 3, self%nd == 2), "rotation (1 in 2D, 3 in 3D)", w, stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (bad_size(size(center), int(self%nd), "center (one per dimension)", w, stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_solver_set_rigid_motion(self%h, patch, translation, rotation, center), w, stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  subroutine solver_clear_rigid_motions(self, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_solver_clear_rigid_motions(self%h), "solver_clear_rigid_motions", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> d(dim, nv): prescribed displacement in, solution out. With MESHMOVE_STATUS_NOT_CONVERGED in
  !> `stat`, d holds the unconverged solution.
  subroutine solver_solve(self, d, report, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(inout), contiguous :: d(:, :)
    type(meshmove_report), intent(out), optional :: report
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_report) :: r
    real(c_double), allocatable :: p(:, :)
    if (bad_shape(size(d, 1), size(d, 2), self%nd, self%nv, "d", "solver_solve", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    allocate (p, source=d)
    call check(meshmove_solver_solve(self%h, int(size(d), c_int32_t), p, c_null_ptr, d, r), "solver_solve", &
      stat)
    if (present(errmsg)) call message(errmsg)
    if (present(report)) report = r
  end subroutine

  !> One multigrid cycle from d(dim, nv) (read and overwritten); prescribed(dim, nv).
  subroutine solver_cycle(self, prescribed, d, report, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: prescribed(:, :)
    real(c_double), intent(inout), contiguous :: d(:, :)
    type(meshmove_report), intent(out), optional :: report
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_report) :: r
    if (bad_shape(size(prescribed, 1), size(prescribed, 2), self%nd, self%nv, "prescribed", "solver_cycle", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (bad_shape(size(d, 1), size(d, 2), self%nd, self%nv, "d", "solver_cycle", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_solver_cycle(self%h, int(size(d), c_int32_t), prescribed, d, r), "solver_cycle", stat)
    if (present(errmsg)) call message(errmsg)
    if (present(report)) report = r
  end subroutine

  !> The drop-in call: xy(dim, nv) updated in place from the boundary displacement bd(dim, nv).
  !> MESHMOVE_STATUS_INVERTED in `stat`: xy holds the moved mesh, `quality` the inverted cells.
  subroutine solver_move(self, bd, xy, report, quality, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: bd(:, :)
    real(c_double), intent(inout), contiguous :: xy(:, :)
    type(meshmove_report), intent(out), optional :: report
    type(meshmove_quality), intent(out), optional :: quality
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(meshmove_report) :: r
    type(meshmove_quality) :: q
    if (bad_shape(size(bd, 1), size(bd, 2), self%nd, self%nv, "bd", "solver_move", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (bad_shape(size(xy, 1), size(xy, 2), self%nd, self%nv, "xy", "solver_move", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_solver_move(self%h, int(size(xy), c_int32_t), bd, xy, r, q), "solver_move", stat)
    if (present(errmsg)) call message(errmsg)
    if (present(report)) report = r
    if (present(quality)) quality = q
  end subroutine

  !> Moves the boundary to d(dim, nv) in `steps` equal steps (1 ≤ steps ≤ MESHMOVE_MAX_STEPS).
  !> `reports` (optional) receives the first size(reports) step reports.
  subroutine solver_move_in_steps(self, d, steps, reports, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: d(:, :)
    integer(c_int32_t), intent(in) :: steps
    type(meshmove_step_report), intent(out), contiguous, target, optional :: reports(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(c_ptr) :: rp
    integer(c_int32_t) :: nr
    rp = c_null_ptr
    nr = 0
    if (bad_shape(size(d, 1), size(d, 2), self%nd, self%nv, "d", "solver_move_in_steps", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    if (present(reports)) then
      if (size(reports) > 0) then
        rp = c_loc(reports)
        nr = int(size(reports), c_int32_t)
      end if
    end if
    call check(meshmove_solver_move_in_steps(self%h, int(size(d), c_int32_t), d, steps, nr, rp), &
      "solver_move_in_steps", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The step reports of the last move or move_in_steps (kept after a failure too).
  subroutine solver_step_reports(self, reports, stat, errmsg)
    class(mm_solver), intent(in) :: self
    type(meshmove_step_report), allocatable, target, intent(out) :: reports(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n, cap, s
    n = 0
    s = meshmove_solver_step_reports(self%h, 0_c_int32_t, c_null_ptr, n)
    if (s /= MESHMOVE_STATUS_OK .and. s /= MESHMOVE_STATUS_BUFFER_TOO_SMALL) then
      allocate (reports(0))
      call check(s, "solver_step_reports", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    allocate (reports(n))
    if (n == 0) then
      call check(s, "solver_step_reports", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    cap = n
    call check(meshmove_solver_step_reports(self%h, cap, c_loc(reports), n), "solver_step_reports", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Seconds of re-reference, solve and quality check of each step of the last move or
  !> move_in_steps, in the order of the step seconds.
  subroutine solver_step_seconds(self, seconds, stat, errmsg)
    class(mm_solver), intent(in) :: self
    type(meshmove_step_seconds), allocatable, target, intent(out) :: seconds(:)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    integer(c_int32_t) :: n, cap, s
    n = 0
    s = meshmove_solver_step_seconds(self%h, 0_c_int32_t, c_null_ptr, n)
    if (s /= MESHMOVE_STATUS_OK .and. s /= MESHMOVE_STATUS_BUFFER_TOO_SMALL) then
      allocate (seconds(0))
      call check(s, "solver_step_seconds", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    allocate (seconds(n))
    if (n == 0) then
      call check(s, "solver_step_seconds", stat)
      if (present(errmsg)) call message(errmsg)
      return
    end if
    cap = n
    call check(meshmove_solver_step_seconds(self%h, cap, c_loc(seconds), n), "solver_step_seconds", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Automatic sub-stepping: a step that would invert a cell, fall below min_volume_ratio or not
  !> converge is split in halves, down to 1/max_substeps of the step (0 or 1: no splitting).
  subroutine solver_set_substepping(self, max_substeps, min_volume_ratio, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(in) :: max_substeps
    real(c_double), intent(in) :: min_volume_ratio
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_solver_set_substepping(self%h, max_substeps, min_volume_ratio), "solver_set_substepping", &
      stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> What each later step is solved from: MESHMOVE_REFERENCE_INCREMENTAL or _ORIGINAL.
  subroutine solver_set_reference_mode(self, mode, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    integer(c_int32_t), intent(in) :: mode
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_solver_set_reference_mode(self%h, mode), "solver_set_reference_mode", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The progress callback of move and move_in_steps: `progress = c_funloc(f)` of an
  !> integer(c_int32_t) bind(c) function f(user_data, report, steps) with `type(c_ptr), value ::
  !> user_data`, `type(meshmove_step_report), intent(in) :: report`, `integer(c_int32_t), value
  !> :: steps`, called after every sub-step on the calling thread; it returns 0 to go on and
  !> anything else to cancel (MESHMOVE_STATUS_CANCELLED, the solver as before the call).
  !> `c_null_funptr` removes it. f must return normally.
  subroutine solver_set_progress(self, progress, user_data, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    type(c_funptr), intent(in) :: progress
    type(c_ptr), intent(in), optional :: user_data
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    type(c_ptr) :: ud
    ud = c_null_ptr
    if (present(user_data)) ud = user_data
    call check(meshmove_solver_set_progress(self%h, progress, ud), "solver_set_progress", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Asks the call running on the solver (from another thread, or the next call) to stop
  !> within one multigrid cycle: it returns MESHMOVE_STATUS_CANCELLED, the solver as before it.
  !> The one call allowed while another thread's call holds the solver.
  subroutine solver_cancel(self, stat, errmsg)
    class(mm_solver), intent(in) :: self
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_solver_cancel(self%h), "solver_cancel", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Makes xy(dim, nv) the solver's reference mesh.
  subroutine solver_set_reference(self, xy, stat, errmsg)
    class(mm_solver), intent(inout) :: self
    real(c_double), intent(in), contiguous :: xy(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (bad_shape(size(xy, 1), size(xy, 2), self%nd, self%nv, "xy", "solver_set_reference", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_solver_set_reference(self%h, int(size(xy), c_int32_t), xy), "solver_set_reference", &
      stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The current coordinates as xy(dim, nv).
  subroutine solver_coords(self, xy, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), allocatable, intent(out) :: xy(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    allocate (xy(self%nd, self%nv))
    call check(meshmove_solver_get_coords(self%h, int(size(xy), c_int32_t), xy), "solver_get_coords", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The displacement of the last solve, cycle or move as d(dim, nv).
  subroutine solver_displacement(self, d, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), allocatable, intent(out) :: d(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    allocate (d(self%nd, self%nv))
    call check(meshmove_solver_get_displacement(self%h, int(size(d), c_int32_t), d), "solver_get_displacement", &
      stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> The displacement since the mesh the solver was created with, d(dim, nv): the sum of every
  !> move's increment and move_in_steps' total so far (displacement gives the last call's).
  subroutine solver_total_displacement(self, d, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), allocatable, intent(out) :: d(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    allocate (d(self%nd, self%nv))
    call check(meshmove_solver_get_total_displacement(self%h, int(size(d), c_int32_t), d), &
      "solver_get_total_displacement", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Quality of the current positions against the mesh the solver was created with (a move's
  !> quality compares with the mesh before that move).
  subroutine solver_total_quality(self, quality, stat, errmsg)
    class(mm_solver), intent(in) :: self
    type(meshmove_quality), intent(out) :: quality
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    call check(meshmove_solver_total_quality(self%h, quality), "solver_total_quality", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Quality of the reference mesh moved by d(dim, nv).
  subroutine solver_quality(self, d, quality, stat, errmsg)
    class(mm_solver), intent(in) :: self
    real(c_double), intent(in), contiguous :: d(:, :)
    type(meshmove_quality), intent(out) :: quality
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (bad_shape(size(d, 1), size(d, 2), self%nd, self%nv, "d", "solver_quality", stat)) then
      if (present(errmsg)) call message(errmsg)
      return
    end if
    call check(meshmove_solver_quality(self%h, int(size(d), c_int32_t), d, quality), "solver_quality", stat)
    if (present(errmsg)) call message(errmsg)
  end subroutine

  !> Writes the reference mesh moved by d(dim, nv); absent: the mesh the solver was created with,
  !> moved by the total displacement since (its ratios then measure every move so far).
  subroutine solver_write_vtu(self, path, d, stat, errmsg)
    class(mm_solver), intent(in) :: self
    character(*), intent(in) :: path
    real(c_double), intent(in), contiguous, target, optional :: d(:, :)
    integer(c_int32_t), intent(out), optional :: stat
    character(len=:), allocatable, intent(out), optional :: errmsg
    if (present(d)) then
      if (bad_shape(size(d, 1), size(d, 2), self%nd, self%nv, "d", "solver_write_vtu", stat)) then
        if (present(errmsg)) call message(errmsg)
        return
      end if
      call check(meshmove_solver_write_vtu(self%h, cstr(path), int(size(d), c_int32_t), c_loc(d)), &
        "solver_write_vtu", stat)
      if (present(errmsg)) call message(errmsg)
    else
      call check(meshmove_solver_write_vtu(self%h, cstr(path), 0_c_int32_t, c_null_ptr), "solver_write_vtu", &
        stat)
      if (present(errmsg)) call message(errmsg)
    end if
  end subroutine
end module meshmove
