! Reads what the code_saturne example wrote and checks it against meshmove run outside
! code_saturne.
! Usage: check_steps FACES COORDS [reference]
!   FACES   meshmove_faces.bin: the mesh as code_saturne's faces give it (usalcl's first call)
!   COORDS  coords.bin: the step number and the coordinates code_saturne ends each time step with
! Prints for every step the smallest cell volume ratio against the original mesh (meshmove's
! measure, the same for either mover) and the largest over the steps. With `reference`, the
! same motion is also made by meshmove alone (the module meshmove_cylinder that usalcl uses,
! fed the same faces), and code_saturne's coordinates at the end of step n are compared with
! meshmove's result of step n - 1: code_saturne moves its vertices to what usalcl imposed in
! step n after that step's user operations, so the flow solve of step n + 1 runs on them and
! the coordinates written at the end of step n are still those of step n - 1. It fails when a
! difference exceeds 1e-12, a cell is inverted or a step is missing. The amplitude of the
! motion is read from CS_AMPLITUDE as the run's usalcl read it (run.sh sets it).
program check_steps
  use, intrinsic :: iso_c_binding
  use meshmove
  use meshmove_cylinder
  implicit none (type, external)
  real(c_double), parameter :: tol = 1e-12_c_double
  type(face_mesh) :: m
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: measure
  type(meshmove_quality) :: q
  character(len=4096) :: faces_path, coords_path, mode
  real(c_double), allocatable :: xyz(:, :), previous(:, :)
  real(c_double) :: worst_ratio, diff, worst_diff
  integer(c_int32_t) :: inverted
  integer(c_int32_t) :: nv, step, stat
  character(len=:), allocatable :: msg
  integer :: u, ios, count, expected
  logical :: reference

  if (command_argument_count() < 2) error stop "usage: check_steps FACES COORDS [reference]"
  call get_command_argument(1, faces_path)
  call get_command_argument(2, coords_path)
  mode = ""
  if (command_argument_count() > 2) call get_command_argument(3, mode)
  reference = mode == "reference"

  call read_motion()
  call read_face_mesh(m, trim(faces_path))
  ! The volume ratios are measured by a solver on the original mesh (its reference).
  call mesh%create_from_faces(m%coords, m%offsets, m%vertices, m%owner, m%neighbour, m%patch, m%num_cells)
  call bcs%create()
  call measure%create(mesh, bcs)
  call bcs%free()
  call mesh%free()
  if (reference) then
    call start_meshmove(m, stat, msg)
    if (stat /= MESHMOVE_STATUS_OK) call fail("meshmove's solver: " // msg)
  end if

  open (newunit=u, file=trim(coords_path), access="stream", form="unformatted", status="old", action="read")
  read (u) nv
  if (nv /= size(m%coords, 2)) error stop "coords.bin and meshmove_faces.bin disagree on the vertices"
  allocate (xyz(3, nv))
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
  do
    read (u, iostat=ios) step, xyz
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
  close (u)
  call measure%free()
  if (reference) call stop_meshmove()
  if (count == 0) error stop "coords.bin holds no step"
  write (*, "(a, i0, a, f14.10)") "steps: ", count, ", min volume ratio over the motion: ", worst_ratio
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
