! At the end of every time step: the step's number and the coordinates code_saturne ends it
! with, appended to coords.bin (native integers and reals, read by check_steps.f90), and to
! steps.txt the wall-clock seconds of the step (since the last step's end) and of meshmove's
! move in it (0 when code_saturne moves the mesh itself).
!
! On several ranks each rank appends its own vertices to coords_rank<rank>.bin, whose header
! also holds the rank, the number of ranks and the global number of each of its vertices (so a
! check can gather them), and rank 0 alone writes steps.txt.

subroutine cs_f_user_extra_operations(nvar, nscal, dt)
  use, intrinsic :: iso_c_binding, only: c_int32_t, c_int64_t
  use optcal, only: ntcabs
  use parall, only: irangp, nrangp
  use mesh, only: ncelet, nnod, xyznod
  use meshmove_cylinder, only: move_seconds
  use saturne_ranks, only: saturne_global_vertices
  implicit none
  integer nvar, nscal
  double precision dt(ncelet)
  ! Units of the two files (no NEWUNIT in Fortran 2003, which code_saturne compiles user files as).
  integer, parameter :: coords_unit = 9072, steps_unit = 9073
  integer, parameter :: int64 = selected_int_kind(18)
  logical, save :: first = .true.
  integer(int64), save :: last = 0
  double precision, save :: last_move = 0
  integer(int64) :: now, rate
  integer(c_int64_t), allocatable :: gnum(:)
  character(len=64) :: name
  call system_clock(now, rate)
  if (first) then
    first = .false.
    if (irangp < 0) then
      open (coords_unit, file="coords.bin", access="stream", form="unformatted", status="replace")
      write (coords_unit) nnod
    else
      write (name, "(a, i0, a)") "coords_rank", irangp, ".bin"
      open (coords_unit, file=trim(name), access="stream", form="unformatted", status="replace")
      allocate (gnum(nnod))
      call saturne_global_vertices(int(nnod, c_int32_t), gnum)
      write (coords_unit) nnod, irangp, nrangp, gnum
    end if
    if (irangp <= 0) then
      open (steps_unit, file="steps.txt", status="replace")
      write (steps_unit, "(a)") "# step  seconds  meshmove_seconds"
    end if
  else if (irangp <= 0) then
    write (steps_unit, "(i6, 2es14.6)") ntcabs, real(now - last) / real(rate), move_seconds - last_move
    flush (steps_unit)
  end if
  last = now
  last_move = move_seconds
  write (coords_unit) ntcabs, xyznod(:, 1:nnod)
  flush (coords_unit)
end subroutine cs_f_user_extra_operations
