! The paper's first case split into slabs of x over the ranks of MPI_COMM_WORLD: the box
! [0,1]x[-1,0] as a 24 x 24 grid of triangles, bottom FIXED, top CLAMPED and raised to
! y = 0.25 cos(2 pi x), sides CLAMPED in x and FREE in y; the biharmonic. Every rank owns the
! cells whose centres lie in its slab and holds one layer of ghost cells around them, gives
! meshmove its local mesh with the global id of each vertex, and moves it with the distributed
! solver (module meshmove_mpi); it checks its part against the serial solver on the whole mesh
! (to 1e-10 of the motion, both solved to 1e-12): a solve, then the whole motion in two steps
! (meshmove_dist_solver_move_in_steps beside the serial meshmove_solver_move_in_steps).
! Run: mpirun -np 1..4 free_surface_mpi_f
program free_surface_mpi
  use, intrinsic :: iso_c_binding
  use mpi_f08
  use meshmove_c
  use meshmove_mpi
  use box_grid, only: make_box_grid
  implicit none (type, external)
  integer(c_int32_t), parameter :: bottom = 1, right = 2, top = 3, left = 4
  integer, parameter :: n = 24
  real(c_double), parameter :: pi = acos(-1.0_c_double)
  real(c_double), allocatable :: xy(:, :), d(:, :), ref(:, :), lxy(:, :), ld(:, :), out(:, :), moved(:, :)
  type(meshmove_dist_step_report) :: steps(2)
  integer(c_int32_t), allocatable :: cells(:, :), edges(:, :), patches(:), lcells(:, :), ledges(:, :), &
    lpatches(:), ghost(:), types(:), ltypes(:)
  integer(c_int64_t), allocatable :: gids(:)
  integer, allocatable :: owner(:), local(:)
  logical, allocatable :: touched(:), kept(:)
  type(c_ptr) :: mesh, lmesh, bcs, options, serial, dmesh, dsolver
  type(meshmove_report) :: rep
  type(meshmove_dist_report) :: drep
  integer :: rank, nranks, c, e, v, nv, nc, nf, failed, any_failed
  real(c_double) :: scale, worst, stepped

  call MPI_Init()
  call MPI_Comm_rank(MPI_COMM_WORLD, rank)
  call MPI_Comm_size(MPI_COMM_WORLD, nranks)
  call make_box_grid(n, n, [0.0_c_double, 1.0_c_double, -1.0_c_double, 0.0_c_double], [bottom, right, top, left], &
    xy, cells, edges, patches)
  allocate (d(2, size(xy, 2)), ref(2, size(xy, 2)))
  d = 0
  do v = 1, size(xy, 2)
    if (xy(2, v) == 0) d(2, v) = 0.25_c_double * cos(2 * pi * xy(1, v))
  end do
  call check(meshmove_bcs_create(bcs), "bcs_create")
  call check(meshmove_bcs_set_kinds(bcs, bottom, MESHMOVE_KIND_FIXED), "bcs_set_kinds")
  call check(meshmove_bcs_set_kinds(bcs, top, MESHMOVE_KIND_CLAMPED), "bcs_set_kinds")
  do c = 1, 2
    call check(meshmove_bcs_set_kind(bcs, merge(left, right, c == 1), 0, MESHMOVE_KIND_CLAMPED), "bcs_set_kind")
    call check(meshmove_bcs_set_kind(bcs, merge(left, right, c == 1), 1, MESHMOVE_KIND_FREE), "bcs_set_kind")
  end do

  ! The serial reference on the whole mesh, on every rank.
  allocate (types(size(cells, 2)))
  types = MESHMOVE_CELL_TYPE_TRIANGLE
  call check(meshmove_mesh_create(2, size(xy, 2), xy, size(cells, 2), c_null_ptr, size(cells), cells, types, &
    size(edges, 2), c_null_ptr, size(edges), edges, patches, c_null_ptr, 1, mesh), "mesh_create")
  call check(meshmove_options_create(options), "options_create")
  call check(meshmove_options_set_tol(options, 1e-12_c_double), "options_set_tol")
  ! The biharmonic's distributed solve is preconditioned by its smoother alone: more iterations.
  call check(meshmove_options_set_max_cycles(options, 5000), "options_set_max_cycles")
  call check(meshmove_solver_create(mesh, bcs, options, serial), "solver_create")
  call check(meshmove_solver_solve(serial, size(d), d, c_null_ptr, ref, rep), "solver_solve")
  scale = maxval(abs(ref))

  ! This rank's part: its slab's cells, then every cell sharing a vertex with them as a ghost.
  allocate (owner(size(cells, 2)), touched(size(xy, 2)), kept(size(cells, 2)), local(size(xy, 2)))
  do c = 1, size(cells, 2)
    owner(c) = min(int(sum(xy(1, cells(:, c))) / 3 * nranks), nranks - 1)
  end do
  touched = .false.
  do c = 1, size(cells, 2)
    if (owner(c) == rank) touched(cells(:, c)) = .true.
  end do
  do c = 1, size(cells, 2)
    kept(c) = any(touched(cells(:, c)))
  end do
  local = 0
  nv = 0
  do c = 1, size(cells, 2)
    if (.not. kept(c)) cycle
    do e = 1, 3
      if (local(cells(e, c)) == 0) then
        nv = nv + 1
        local(cells(e, c)) = nv
      end if
    end do
  end do
  nc = count(kept)
  allocate (lxy(2, nv), ld(2, nv), out(2, nv), gids(nv), lcells(3, nc), ghost(nc), ltypes(nc))
  do v = 1, size(xy, 2)
    if (local(v) == 0) cycle
    lxy(:, local(v)) = xy(:, v)
    ld(:, local(v)) = d(:, v)
    gids(local(v)) = v
  end do
  nc = 0
  do c = 1, size(cells, 2)
    if (.not. kept(c)) cycle
    nc = nc + 1
    lcells(:, nc) = local(cells(:, c))
    ghost(nc) = merge(0, 1, owner(c) == rank)
  end do
  ltypes = MESHMOVE_CELL_TYPE_TRIANGLE
  ! The tagged edges of the part's cells.
  nf = count(local(edges(1, :)) > 0 .and. local(edges(2, :)) > 0)
  allocate (ledges(2, nf), lpatches(nf))
  nf = 0
  do e = 1, size(edges, 2)
    if (local(edges(1, e)) == 0 .or. local(edges(2, e)) == 0) cycle
    nf = nf + 1
    ledges(:, nf) = local(edges(:, e))
    lpatches(nf) = patches(e)
  end do
  call check(meshmove_mesh_create(2, nv, lxy, nc, c_null_ptr, size(lcells), lcells, ltypes, nf, c_null_ptr, &
    size(ledges), ledges, lpatches, c_null_ptr, 1, lmesh), "local mesh_create")
  call check(meshmove_dist_mesh_create_f(MPI_COMM_WORLD%MPI_VAL, lmesh, gids, nv, ghost, nc, dmesh), &
    "dist_mesh_create_f")
  call check(meshmove_mesh_free(lmesh), "mesh_free")
  call check(meshmove_dist_solver_create(dmesh, bcs, options, dsolver), "dist_solver_create")
  call check(meshmove_dist_solver_solve(dsolver, ld, size(ld), out, size(out), drep), "dist_solver_solve")

  worst = 0
  do v = 1, size(xy, 2)
    if (local(v) > 0) worst = max(worst, maxval(abs(out(:, local(v)) - ref(:, v))))
  end do
  failed = 0
  if (worst > 1e-10_c_double * scale) then
    print '(a, i0, a, es10.3)', "rank ", rank, ": differs from the serial solver by ", worst
    failed = 1
  end if
  ! The whole motion in two steps, here and serially; the moved positions agree.
  call check(meshmove_dist_solver_move_in_steps(dsolver, ld, size(ld), 2, out, size(out), 2, steps), &
    "dist_solver_move_in_steps")
  call check(meshmove_solver_move_in_steps(serial, size(d), d, 2, 0, c_null_ptr), "solver_move_in_steps")
  allocate (moved(2, size(xy, 2)))
  call check(meshmove_solver_get_coords(serial, size(moved), moved), "solver_get_coords")
  stepped = 0
  do v = 1, size(xy, 2)
    if (local(v) > 0) stepped = max(stepped, maxval(abs(out(:, local(v)) - moved(:, v))))
  end do
  if (stepped > 1e-10_c_double * scale .or. steps(2)%step%accepted /= 1) then
    print '(a, i0, a, es10.3)', "rank ", rank, ": in two steps, differs from the serial solver by ", stepped
    failed = 1
  end if
  if (rank == 0) print '(a, i0, a, i0, a, es9.2, a, es9.2, a, f9.6)', "free_surface_mpi on ", nranks, " ranks: ", &
    drep%iterations, " iterations, largest difference ", worst / scale, " of the motion (in two steps ", &
    stepped / scale, "), min area ratio ", drep%min_area_ratio
  call check(meshmove_dist_solver_free(dsolver), "dist_solver_free")
  call check(meshmove_dist_mesh_free(dmesh), "dist_mesh_free")
  call check(meshmove_solver_free(serial), "solver_free")
  call check(meshmove_options_free(options), "options_free")
  call check(meshmove_mesh_free(mesh), "mesh_free")
  call check(meshmove_bcs_free(bcs), "bcs_free")
  call MPI_Allreduce(failed, any_failed, 1, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD)
  call MPI_Finalize()
  if (any_failed /= 0) error stop "a rank's part differs from the serial solver"

contains

  subroutine check(st, what)
    integer(c_int32_t), intent(in) :: st
    character(*), intent(in) :: what
    if (st /= MESHMOVE_STATUS_OK) then
      print '(a, a, a, i0)', "meshmove_", what, " failed with status ", st
      error stop 1
    end if
  end subroutine
end program
