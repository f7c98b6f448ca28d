! Reads what the code_saturne example wrote and checks it against meshmove run outside
! code_saturne.
! Usage: check_steps FACES COORDS [COORDS ...] [reference]
!   FACES   meshmove_faces.bin: the mesh as code_saturne's faces give it (a serial run's
!           usalcl, first call)
!   COORDS  coords.bin: the step number and the coordinates code_saturne ends each time step with;
!           or, for a run on N ranks, its N files coords_rank<r>.bin, each with the global number
!           of its vertices, gathered by global number (a vertex on several ranks must have the
!           same coordinates on each, bit for bit)
! Prints for every step the smallest cell volume ratio against the original mesh (meshmove's
! measure, the same for either mover) and the largest over the steps. With `reference`, the
! same motion is also made by meshmove alone (the module meshmove_cylinder that usalcl uses,
! fed the same faces), and code_saturne's coordinates at the end of step n are compared with
! meshmove's result of step n - 1: code_saturne moves its vertices to what usalcl imposed in
! step n after that step's user operations, so the flow solve of step n + 1 runs on them and
! the coordinates written at the end of step n are still those of step n - 1. It fails when a
! difference exceeds 1e-12 (serial: the same solver), or on several ranks 1e-10 of the motion's
! amplitude (the distributed solver and this serial one both solved to ranks_tol), a cell is
! inverted or a step is missing. The amplitude of the motion is read from CS_AMPLITUDE as the
! run's usalcl read it (run.sh sets it). The global numbers of the ranks' vertices are the
! serial run's vertex numbers (code_saturne numbers a serial run's vertices globally).
! The coordinates a run wrote at the end of each time step: one file (coords.bin, the serial
! run's vertices) or one file per rank (coords_rank<r>.bin: the rank's vertices with their
! global numbers), read step by step into the global vertex order.
module step_reader
  use, intrinsic :: iso_c_binding
  implicit none (type, external)
  private
  public :: open_steps, read_step, close_steps

  !> The open files: a unit per file, and per rank file its vertices' global numbers.
  type :: step_part
    integer :: unit = -1
    integer(c_int64_t), allocatable :: gnum(:)
  end type
  type, public :: step_files
    type(step_part), allocatable :: parts(:)
  end type

contains

  !> Opens the files of a run of nv vertices: one serial file or one file per rank (ranks 0 to
  !> N - 1, in any order); checks that every vertex is on some rank.
  subroutine open_steps(files, paths, nv)
    type(step_files), intent(out) :: files
    character(len=*), intent(in) :: paths(:)
    integer, intent(in) :: nv
    integer(c_int32_t) :: n, rank, nranks
    logical, allocatable :: seen(:), held(:)
    integer :: i
    allocate (files%parts(size(paths)), seen(size(paths)), held(nv))
    seen = .false.
    held = .false.
    do i = 1, size(paths)
      open (newunit=files%parts(i)%unit, file=trim(paths(i)), access="stream", form="unformatted", status="old", &
        action="read")
      read (files%parts(i)%unit) n
      if (size(paths) == 1) then
        if (n /= nv) error stop "coords.bin and meshmove_faces.bin disagree on the vertices"
        return
      end if
      read (files%parts(i)%unit) rank, nranks
      if (nranks /= size(paths)) error stop "a rank's file names another number of ranks than the files given"
      if (rank < 0 .or. rank >= nranks) error stop "a rank's file names a rank out of range"
      if (seen(rank + 1)) error stop "two files of the same rank"
      seen(rank + 1) = .true.
      allocate (files%parts(i)%gnum(n))
      read (files%parts(i)%unit) files%parts(i)%gnum
      if (any(files%parts(i)%gnum < 1 .or. files%parts(i)%gnum > nv)) error stop "a global vertex number out of range"
      held(files%parts(i)%gnum) = .true.
    end do
    if (.not. all(held)) error stop "a vertex is on no rank"
  end subroutine

  !> The next time step: its number and every vertex's coordinates (ios /= 0 at the end of a
  !> file). rank_diff receives the largest difference seen so far between two ranks' copies of
  !> a vertex.
  subroutine read_step(files, step, xyz, rank_diff, ios)
    type(step_files), intent(inout) :: files
    integer(c_int32_t), intent(out) :: step
    real(c_double), intent(out) :: xyz(:, :)
    real(c_double), intent(inout) :: rank_diff
    integer, intent(out) :: ios
    real(c_double), allocatable :: part(:, :)
    logical, allocatable :: filled(:)
    integer(c_int32_t) :: s
    integer :: i, k
    ios = 0
    step = 0
    if (size(files%parts) == 1) then
      read (files%parts(1)%unit, iostat=ios) step, xyz
      return
    end if
    allocate (filled(size(xyz, 2)))
    filled = .false.
    do i = 1, size(files%parts)
      allocate (part(3, size(files%parts(i)%gnum)))
      read (files%parts(i)%unit, iostat=ios) s, part
      if (ios /= 0) return
      if (i == 1) step = s
      if (s /= step) error stop "the ranks' files disagree on the time step"
      do k = 1, size(files%parts(i)%gnum)
        associate (g => files%parts(i)%gnum(k))
          if (filled(g)) then
            rank_diff = max(rank_diff, maxval(abs(xyz(:, g) - part(:, k))))
          else
            xyz(:, g) = part(:, k)
            filled(g) = .true.
          end if
        end associate
      end do
      deallocate (part)
    end do
  end subroutine

  subroutine close_steps(files)
    type(step_files), intent(inout) :: files
    integer :: i
    do i = 1, size(files%parts)
      close (files%parts(i)%unit)
    end do
  end subroutine
end module step_reader

program check_steps
  use, intrinsic :: iso_c_binding
  use meshmove
  use meshmove_cylinder
  use step_reader
  implicit none (type, external)
  type(face_mesh) :: m
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: measure
  type(meshmove_quality) :: q
  character(len=4096) :: faces_path, mode
  character(len=4096), allocatable :: coords_paths(:)
  real(c_double), allocatable :: xyz(:, :), previous(:, :)
  real(c_double) :: worst_ratio, diff, worst_diff, tol, rank_diff
  integer(c_int32_t) :: inverted
  integer(c_int32_t) :: step, stat
  character(len=:), allocatable :: msg
  integer :: i, nfiles, ios, count, expected
  logical :: reference
  type(step_files) :: files

  nfiles = command_argument_count() - 1
  if (nfiles < 1) error stop "usage: check_steps FACES COORDS [COORDS ...] [reference]"
  call get_command_argument(1, faces_path)
  call get_command_argument(nfiles + 1, mode)
  reference = mode == "reference"
  if (reference) nfiles = nfiles - 1
  if (nfiles < 1) error stop "usage: check_steps FACES COORDS [COORDS ...] [reference]"
  allocate (coords_paths(nfiles))
  do i = 1, nfiles
    call get_command_argument(i + 1, coords_paths(i))
  end do

  call read_motion()
  call read_face_mesh(m, trim(faces_path))
  ! The volume ratios are measured by a solver on the original mesh (its reference).
  call mesh%create_from_faces(m%coords, m%offsets, m%vertices, m%owner, m%neighbour, m%patch, m%num_cells)
  call bcs%create()
  call measure%create(mesh, bcs)
  call bcs%free()
  call mesh%free()
  ! A serial run is the same solver as the reference; a run on several ranks the distributed one.
  if (nfiles == 1) then
    tol = 1e-12_c_double
    if (reference) call start_meshmove(m, stat, msg)
  else
    tol = 1e-10_c_double * amplitude
    if (reference) call start_meshmove(m, stat, msg, ranks_tol)
  end if
  if (reference .and. stat /= MESHMOVE_STATUS_OK) call fail("meshmove's solver: " // msg)

  call open_steps(files, coords_paths, size(m%coords, 2))
  allocate (xyz(3, size(m%coords, 2)))
  allocate (previous, source=m%coords)
  worst_ratio = huge(1.0_c_double)
  worst_diff = 0
  inverted = 0
  count = 0
  expected = 1
  if (reference) then
    write (*, "(a)") "# step  min_volume_ratio  inverted  max|x_cs - x_meshmove|"
  else
    write (*, "(a)") "# step  min_volume_ratio  inverted"
  end if
  rank_diff = 0
  do
    call read_step(files, step, xyz, rank_diff, ios)
    if (ios /= 0) exit
    if (step /= expected) error stop "coords.bin: a time step is missing"
    expected = expected + 1
    count = count + 1
    call measure%quality(xyz - m%coords, q)
    worst_ratio = min(worst_ratio, q%min_volume_ratio)
    inverted = max(inverted, q%inverted)
    if (reference) then
      ! meshmove's result of step n - 1, made from the same faces and motion.
      if (step > 1) then
        call advance_meshmove(step - 1, stat, msg)
        if (stat /= MESHMOVE_STATUS_OK) call fail("meshmove's step: " // msg)
        previous = moved
      end if
      diff = maxval(abs(xyz - previous))
      worst_diff = max(worst_diff, diff)
      write (*, "(i6, f18.12, i10, es26.3)") step, q%min_volume_ratio, q%inverted, diff
    else
      write (*, "(i6, f18.12, i10)") step, q%min_volume_ratio, q%inverted
    end if
  end do
  call close_steps(files)
  call measure%free()
  if (reference) call stop_meshmove()
  if (count == 0) error stop "coords.bin holds no step"
  write (*, "(a, i0, a, f14.10)") "steps: ", count, ", min volume ratio over the motion: ", worst_ratio
  if (nfiles > 1) then
    write (*, "(a, i0, a, es10.3)") "ranks: ", nfiles, ", largest difference between two ranks' copies of a vertex: ", &
      rank_diff
    if (rank_diff /= 0) error stop "the ranks disagree on a vertex they share"
  end if
  if (reference) then
    write (*, "(a, es10.3, a, es8.1, a)") "largest difference from meshmove's own steps: ", worst_diff, &
      " (tolerance ", tol, ")"
    if (.not. (worst_diff <= tol)) error stop "code_saturne's coordinates differ from meshmove's"
    if (inverted > 0) error stop "meshmove's mesh has inverted cells"
  end if
contains

  subroutine fail(text)
    character(*), intent(in) :: text
    write (*, "(a)") text
    error stop 1
  end subroutine
end program check_steps
