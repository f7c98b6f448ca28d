! meshmove_mpi.f90: Fortran bindings of the distributed calls (include/meshmove_mpi.h), for a
! library built with the `mpi` feature (CMake option MESHMOVE_WITH_MPI). Raw bind(c) interfaces,
! one per C function, as the module meshmove_c has for the serial ones; the local mesh and the
! boundary conditions are meshmove_c's handles (type(c_ptr)).
!
! The communicator is Fortran's integer handle: an `mpi` program passes MPI_COMM_WORLD (or its
! own communicator), an `mpi_f08` one comm%MPI_VAL; the library converts it with MPI_Comm_f2c and
! duplicates it. Every call is collective over that communicator and returns the same status on
! every rank. Vertex indices are the local mesh's; global ids are any 64-bit integers >= 0.
module meshmove_mpi
  use, intrinsic :: iso_c_binding
  use meshmove_c, only: meshmove_step_report
  implicit none (type, external)
  public

  !> How a distributed solve went, the same on every rank.
  type, bind(c) :: meshmove_dist_report
    integer(c_int32_t) :: iterations
    real(c_double) :: rel_residual
    integer(c_int32_t) :: inverted
    real(c_double) :: min_area_ratio, max_area_ratio, min_angle_deg
    integer(c_int32_t) :: worst_rank
  end type

  !> What one sub-step of a distributed move did (the same on every rank but the seconds): the
  !> serial step report and the rank of the smallest area (volume) ratio.
  type, bind(c) :: meshmove_dist_step_report
    type(meshmove_step_report) :: step
    integer(c_int32_t) :: worst_rank
  end type

  interface
    !> This rank's part of a distributed mesh from its local mesh (its owned cells, and any ghost
    !> cells: the library fetches those it lacks), the global id of each local vertex and the
    !> ghost flags of its cells (non-zero: another rank's).
    integer(c_int32_t) function meshmove_dist_mesh_create_f(comm, local, global_ids, num_ids, ghost_cells, &
        num_ghost, out) bind(c)
      import :: c_int32_t, c_int64_t, c_ptr
      integer(c_int32_t), value :: comm, num_ids, num_ghost
      type(c_ptr), value :: local
      integer(c_int64_t), intent(in) :: global_ids(*)
      integer(c_int32_t), intent(in) :: ghost_cells(*)
      type(c_ptr), intent(out) :: out
    end function
    !> This rank's part of a distributed mesh from its own cells given by their faces (the arrays
    !> of meshmove_mesh_create_from_faces; a face to another rank's cell has that side below
    !> index_base and a patch below 0), and the global id of each local vertex. The library
    !> fetches the other ranks' cells around this rank's vertices.
    integer(c_int32_t) function meshmove_dist_mesh_create_from_faces_f(comm, dim, num_vertices, coords, num_faces, &
        face_offsets, num_face_vertices, face_connectivity, face_owner, face_neighbour, face_patch, num_cells, &
        cell_region, index_base, global_ids, out) bind(c)
      import :: c_int32_t, c_int64_t, c_double, c_ptr
      integer(c_int32_t), value :: comm, dim, num_vertices, num_faces, num_face_vertices, num_cells, index_base
      real(c_double), intent(in) :: coords(*)
      integer(c_int32_t), intent(in) :: face_offsets(*), face_connectivity(*), face_owner(*), face_neighbour(*), &
        face_patch(*)
      type(c_ptr), value :: cell_region
      integer(c_int64_t), intent(in) :: global_ids(*)
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_dist_mesh_free(mesh) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh
    end function
    integer(c_int32_t) function meshmove_dist_mesh_sizes(mesh, dim, local_vertices, owned_vertices, &
        global_vertices) bind(c)
      import :: c_int32_t, c_int64_t, c_ptr
      type(c_ptr), value :: mesh
      integer(c_int32_t), intent(out) :: dim, local_vertices, owned_vertices
      integer(c_int64_t), intent(out) :: global_vertices
    end function
    !> The distributed solver with the serial options handle (meshmove_options_create; c_null_ptr:
    !> the defaults).
    integer(c_int32_t) function meshmove_dist_solver_create(mesh, bcs, options, out) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: mesh, bcs, options
      type(c_ptr), intent(out) :: out
    end function
    integer(c_int32_t) function meshmove_dist_solver_free(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
    end function
    !> Makes `patch` move rigidly in the following solves (collective; every rank sets the same).
    integer(c_int32_t) function meshmove_dist_solver_set_rigid_motion(solver, patch, translation, rotation, center) &
        bind(c)
      import :: c_int32_t, c_double, c_ptr
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: patch
      real(c_double), intent(in) :: translation(*), rotation(*), center(*)
    end function
    integer(c_int32_t) function meshmove_dist_solver_clear_rigid_motions(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
    end function
    !> The displacement of every local vertex (out) from the prescribed one (displacement).
    integer(c_int32_t) function meshmove_dist_solver_solve(solver, displacement, len, out, out_len, report) bind(c)
      import :: c_int32_t, c_double, c_ptr, meshmove_dist_report
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len, out_len
      real(c_double), intent(in) :: displacement(*)
      real(c_double), intent(out) :: out(*)
      type(meshmove_dist_report), intent(out) :: report
    end function
    !> The time step's move (as meshmove_solver_move): coords holds the current positions on entry
    !> and the moved ones on return; displacement is the increment since the last call.
    integer(c_int32_t) function meshmove_dist_solver_move(solver, displacement, len, coords, out_len, report) bind(c)
      import :: c_int32_t, c_double, c_ptr, meshmove_dist_report
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len, out_len
      real(c_double), intent(in) :: displacement(*)
      real(c_double), intent(inout) :: coords(*)
      type(meshmove_dist_report), intent(out) :: report
    end function
    !> Moves the boundary to `prescribed` in `steps` equal steps (as meshmove_solver_move_in_steps);
    !> coords receives the moved positions, reports the first num_reports step reports.
    integer(c_int32_t) function meshmove_dist_solver_move_in_steps(solver, prescribed, len, steps, coords, out_len, &
        num_reports, reports) bind(c)
      import :: c_int32_t, c_double, c_ptr, meshmove_dist_step_report
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: len, steps, out_len, num_reports
      real(c_double), intent(in) :: prescribed(*)
      real(c_double), intent(out) :: coords(*)
      type(meshmove_dist_step_report), intent(out) :: reports(*)
    end function
    !> The step reports of the last move (count receives how many; not collective).
    integer(c_int32_t) function meshmove_dist_solver_step_reports(solver, capacity, reports, count) bind(c)
      import :: c_int32_t, c_ptr, meshmove_dist_step_report
      type(c_ptr), value :: solver
      integer(c_int32_t), value :: capacity
      type(meshmove_dist_step_report), intent(out) :: reports(*)
      integer(c_int32_t), intent(out) :: count
    end function
    !> The progress callback (called on rank 0 only), as meshmove_solver_set_progress.
    integer(c_int32_t) function meshmove_dist_solver_set_progress(solver, progress, user_data) bind(c)
      import :: c_int32_t, c_ptr, c_funptr
      type(c_ptr), value :: solver
      type(c_funptr), value :: progress
      type(c_ptr), value :: user_data
    end function
    integer(c_int32_t) function meshmove_dist_solver_cancel(solver) bind(c)
      import :: c_int32_t, c_ptr
      type(c_ptr), value :: solver
    end function
  end interface
end module
