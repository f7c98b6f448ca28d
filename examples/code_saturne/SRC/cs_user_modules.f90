! The meshmove side of the code_saturne example: the cylinder's motion, the mesh as
! code_saturne's faces give it, and the solver kept for the run. It uses meshmove alone (no
! code_saturne module), so the same file builds the check program that runs the motion outside
! code_saturne (check_steps.f90). code_saturne compiles cs_user_modules.f90 before the other
! user files, which is why the module lives here, and compiles user files as Fortran 2003
! (-std=f2003), which is why it has no NEWUNIT, ERROR STOP or IMPLICIT NONE (TYPE, EXTERNAL).
module meshmove_cylinder
  use, intrinsic :: iso_c_binding
  use meshmove
  implicit none
  private

  integer, parameter :: int64 = selected_int_kind(18)
  ! Fortran units of the face mesh's file (no NEWUNIT in Fortran 2003).
  integer, parameter :: faces_unit = 9071

  !> The boundary zones: gmsh's physical group numbers, which code_saturne's preprocessor keeps
  !> as the zones' names (cylinder.geo), used as meshmove's patch ids.
  integer(c_int32_t), parameter, public :: inlet = 1, outlet = 2, walls = 3, body = 4, symmetry = 5
  integer(c_int32_t), parameter, public :: num_zones = 5

  !> The mesh motion's boundary conditions, one (zone, component, kind) a column, component 0
  !> for all three: the cylinder CLAMPED (it moves rigidly and keeps the spacing at its wall),
  !> the channel's walls, inlet and outlet FIXED, the planes z = 0 and z = 0.5 symmetry planes:
  !> z prescribed (CLAMPED, at rest), x and y FREE, so the vertices slide in them. On a plane
  !> normal to an axis this is the system SLIP makes (docs/DESIGN.md, "Slip walls"), the same
  !> result to the bit, without SLIP's search for each vertex's closest wall point after every
  !> solve. The serial solver and the distributed one (usalcl under MPI) both set these.
  integer(c_int32_t), parameter, public :: conditions(3, 7) = reshape([ &
    inlet, 0, MESHMOVE_KIND_FIXED, outlet, 0, MESHMOVE_KIND_FIXED, walls, 0, MESHMOVE_KIND_FIXED, &
    body, 0, MESHMOVE_KIND_CLAMPED, symmetry, 1, MESHMOVE_KIND_FREE, symmetry, 2, MESHMOVE_KIND_FREE, &
    symmetry, 3, MESHMOVE_KIND_CLAMPED], [3, 7])

  !> The motion: the cylinder (diameter 1, centre (0, 0)) moves across the channel,
  !> y = amplitude sin(2 pi n / steps_per_period) at the end of time step n; the amplitude is
  !> 1 unless the environment variable CS_AMPLITUDE says otherwise (read_motion).
  real(c_double), protected, public :: amplitude = 1
  integer, parameter, public :: steps_per_period = 40

  !> The tolerance of the distributed solver on several ranks, and of the serial one the check
  !> compares it with (check_steps): tight enough that the two meshes agree to well within the
  !> check's 1e-10 of the motion. The serial run keeps meshmove's default tolerance.
  real(c_double), parameter, public :: ranks_tol = 1e-13_c_double

  !> A mesh as finite-volume codes store it: vertices, faces as CSR lists of vertices (1-based
  !> offsets), each face's owner and neighbour cell (0 on the boundary), a zone per boundary face
  !> (-1 on interior faces).
  type, public :: face_mesh
    real(c_double), allocatable :: coords(:, :)
    integer(c_int32_t), allocatable :: offsets(:), vertices(:), owner(:), neighbour(:), patch(:)
    integer(c_int32_t) :: num_cells = 0
  end type

  !> The vertices' positions after the last step meshmove made, (3, number of vertices).
  real(c_double), allocatable, protected, public :: moved(:, :)
  !> The last step meshmove made (0: none yet), and the seconds its move calls took in all.
  integer, protected, public :: last_step = -1
  real(c_double), protected, public :: move_seconds = 0

  !> The centre of the cylinder's rigid motion (on its axis, halfway between the planes).
  real(c_double), parameter, public :: body_centre(3) = [0.0_c_double, 0.0_c_double, 0.25_c_double]

  type(mm_solver), save :: solver

  !> A move of the mesh: the cylinder translated rigidly by `translation` (about `centre`), every
  !> other boundary at rest; xyz holds the positions before the move on entry, after it on return.
  abstract interface
    subroutine body_move(translation, centre, xyz, stat, errmsg)
      import :: c_double, c_int32_t
      real(c_double), intent(in) :: translation(3), centre(3)
      real(c_double), intent(inout) :: xyz(:, :)
      integer(c_int32_t), intent(out) :: stat
      character(len=:), allocatable, intent(out) :: errmsg
    end subroutine
  end interface

  public :: read_motion, body_offset, start_meshmove, begin_motion, advance_meshmove, stop_meshmove, write_face_mesh, &
    read_face_mesh, body_move

contains

  !> The amplitude from the environment variable CS_AMPLITUDE when it is set (the host and the
  !> check program both read it, so both make the same motion).
  subroutine read_motion()
    character(len=64) :: text
    integer :: length, status
    call get_environment_variable("CS_AMPLITUDE", text, length, status)
    if (status == 0 .and. length > 0) read (text, *) amplitude
  end subroutine

  !> The cylinder's displacement across the channel at the end of time step n.
  pure function body_offset(n) result(y)
    integer, intent(in) :: n
    real(c_double) :: y
    real(c_double), parameter :: pi = acos(-1.0_c_double)
    y = amplitude * sin(2 * pi * real(n, c_double) / real(steps_per_period, c_double))
  end function

  !> The solver for the run: the boundary conditions of `conditions`, the biharmonic method,
  !> one thread; solved to `tol` when given (else meshmove's default tolerance). stat is
  !> meshmove's status, errmsg its message.
  subroutine start_meshmove(m, stat, errmsg, tol)
    type(face_mesh), intent(in) :: m
    integer(c_int32_t), intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    real(c_double), intent(in), optional :: tol
    type(mm_mesh) :: mesh
    type(mm_bcs) :: bcs
    type(mm_options) :: options
    integer :: i
    call mesh%create_from_faces(m%coords, m%offsets, m%vertices, m%owner, m%neighbour, m%patch, m%num_cells, &
      stat=stat, errmsg=errmsg)
    if (stat /= MESHMOVE_STATUS_OK) return
    call bcs%create()
    do i = 1, size(conditions, 2)
      if (conditions(2, i) == 0) then
        call bcs%set_kinds(conditions(1, i), conditions(3, i))
      else
        call bcs%set_kind(conditions(1, i), conditions(2, i), conditions(3, i))
      end if
    end do
    call options%create()
    call options%set_threads(1_c_int32_t)
    if (present(tol)) call options%set_tol(tol)
    call solver%create(mesh, bcs, options, stat=stat, errmsg=errmsg)
    call options%free()
    call bcs%free()
    call mesh%free()
    if (stat /= MESHMOVE_STATUS_OK) return
    call begin_motion(m%coords)
  end subroutine

  !> The motion starts from `coords` (step 0), nothing moved yet.
  subroutine begin_motion(coords)
    real(c_double), intent(in) :: coords(:, :)
    moved = coords
    last_step = 0
    move_seconds = 0
  end subroutine

  !> Moves the mesh to the end of time step n (n >= the last step made): the cylinder
  !> translated by the increment since the last step (its rigid motion), every other boundary
  !> at rest. The step already made is not made again (a host may ask twice in one time step).
  !> `move`, when given, makes the move instead of the serial solver (the distributed one).
  subroutine advance_meshmove(n, stat, errmsg, move)
    integer, intent(in) :: n
    integer(c_int32_t), intent(out) :: stat
    character(len=:), allocatable, intent(out) :: errmsg
    procedure(body_move), optional :: move
    real(c_double), allocatable :: bd(:, :)
    real(c_double) :: dy
    integer(int64) :: t0, t1, rate
    stat = MESHMOVE_STATUS_OK
    errmsg = ""
    if (last_step < 0 .or. n < last_step) then
      stat = MESHMOVE_STATUS_INVALID_ARGUMENT
      errmsg = "advance_meshmove: no solver, or a time step before the last one"
      return
    end if
    if (n == last_step) return
    dy = body_offset(n) - body_offset(last_step)
    allocate (bd(3, size(moved, 2)))
    bd = 0
    call system_clock(t0, rate)
    if (present(move)) then
      call move([0.0_c_double, dy, 0.0_c_double], body_centre, moved, stat, errmsg)
    else
      call solver%set_rigid_motion(body, [0.0_c_double, dy, 0.0_c_double], [0.0_c_double, 0.0_c_double, &
        0.0_c_double], body_centre)
      call solver%move(bd, moved, stat=stat, errmsg=errmsg)
    end if
    call system_clock(t1)
    if (stat /= MESHMOVE_STATUS_OK) return
    move_seconds = move_seconds + real(t1 - t0, c_double) / real(rate, c_double)
    last_step = n
  end subroutine

  subroutine stop_meshmove()
    call solver%free()
    last_step = -1
  end subroutine

  !> The face mesh as a stream of native integers and reals (read back by read_face_mesh).
  subroutine write_face_mesh(m, path)
    type(face_mesh), intent(in) :: m
    character(*), intent(in) :: path
    open (faces_unit, file=path, access="stream", form="unformatted", status="replace", action="write")
    write (faces_unit) int(size(m%coords, 2), c_int32_t), int(size(m%owner), c_int32_t), &
      int(size(m%vertices), c_int32_t), m%num_cells
    write (faces_unit) m%coords, m%offsets, m%vertices, m%owner, m%neighbour, m%patch
    close (faces_unit)
  end subroutine

  subroutine read_face_mesh(m, path)
    type(face_mesh), intent(out) :: m
    character(*), intent(in) :: path
    integer(c_int32_t) :: nv, nf, nfv
    open (faces_unit, file=path, access="stream", form="unformatted", status="old", action="read")
    read (faces_unit) nv, nf, nfv, m%num_cells
    allocate (m%coords(3, nv), m%offsets(nf + 1), m%vertices(nfv), m%owner(nf), m%neighbour(nf), m%patch(nf))
    read (faces_unit) m%coords, m%offsets, m%vertices, m%owner, m%neighbour, m%patch
    close (faces_unit)
  end subroutine
end module meshmove_cylinder

! What the user routines ask of code_saturne's C side (meshmove_ranks.c), for the runs on several
! ranks: the global number of each local vertex and code_saturne's communicator.
module saturne_ranks
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t
  implicit none
  private
  public :: saturne_global_vertices, saturne_comm

  interface
    !> The global number (1-based) of each of the rank's n local vertices.
    subroutine saturne_global_vertices(n, gnum) bind(c, name="meshmove_cs_global_vertices")
      import :: c_int32_t, c_int64_t
      integer(c_int32_t), value :: n
      integer(c_int64_t), intent(out) :: gnum(*)
    end subroutine
    !> code_saturne's communicator as Fortran's integer handle.
    integer(c_int32_t) function saturne_comm() bind(c, name="meshmove_cs_comm")
      import :: c_int32_t
    end function
  end interface
end module saturne_ranks
