! The flow's boundary conditions: velocity 1 along x at the inlet (zone 1), a free outlet
! (zone 2), the channel's walls (zone 3) and the planes z = 0, 0.5 (zone 5) symmetry planes, the
! cylinder (zone 4) a wall, moving with the mesh (code_saturne takes its velocity from the
! imposed displacement).

subroutine cs_f_user_boundary_conditions(nvar, nscal, icodcl, itrifb, itypfb, izfppp, dt, rcodcl)
  use paramx, only: ientre, isolib, isymet, iparoi
  use numvar, only: iu, iv, iw
  use mesh, only: nfabor, ncelet
  implicit none
  integer nvar, nscal
  integer icodcl(nfabor, nvar)
  integer itrifb(nfabor), itypfb(nfabor)
  integer izfppp(nfabor)
  double precision dt(ncelet)
  double precision rcodcl(nfabor, nvar, 3)
  integer, allocatable :: lstelt(:)
  integer :: nlelt, i, ifac
  allocate (lstelt(nfabor))
  call getfbr("1", nlelt, lstelt)
  do i = 1, nlelt
    ifac = lstelt(i)
    itypfb(ifac) = ientre
    rcodcl(ifac, iu, 1) = 1.d0
    rcodcl(ifac, iv, 1) = 0.d0
    rcodcl(ifac, iw, 1) = 0.d0
  end do
  call getfbr("2", nlelt, lstelt)
  itypfb(lstelt(1:nlelt)) = isolib
  call getfbr("3 or 5", nlelt, lstelt)
  itypfb(lstelt(1:nlelt)) = isymet
  call getfbr("4", nlelt, lstelt)
  itypfb(lstelt(1:nlelt)) = iparoi
  deallocate (lstelt)
end subroutine cs_f_user_boundary_conditions
