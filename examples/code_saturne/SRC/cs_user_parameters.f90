! The case's parameters: laminar incompressible flow (density 1, viscosity 0.01: Reynolds
! number 100 on the cylinder's diameter), ALE on, a fixed time step of 0.05, as many time steps
! as the environment variable CS_STEPS says (40, one period of the motion, when unset).

subroutine usipph(ixmlpu, iturb, itherm, iale)
  implicit none
  integer ixmlpu
  integer iturb, itherm, iale
  iturb = 0
  itherm = 0
  iale = 1
end subroutine usipph

subroutine usipsu(nmodpp)
  use optcal, only: ntmabs, dtref, idtvar
  use cstphy, only: ro0, viscl0
  use albase, only: nalinf
  implicit none
  integer nmodpp
  character(len=16) :: steps
  integer :: length, status
  call get_environment_variable("CS_STEPS", steps, length, status)
  ntmabs = 40
  if (status == 0 .and. length > 0) read (steps, *) ntmabs
  dtref = 0.05d0
  idtvar = 0
  ro0 = 1.d0
  viscl0 = 0.01d0
  nalinf = 0
end subroutine usipsu
