! Links the installed meshmove from Fortran (module `meshmove`, libmeshmove_fortran + libmeshmove)
! and moves a small mesh: the unit square around a centre vertex, its top edge raised by 0.1.
program consumer
  use, intrinsic :: iso_c_binding
  use meshmove
  implicit none
  type(mm_mesh) :: mesh
  type(mm_bcs) :: bcs
  type(mm_solver) :: solver
  real(c_double) :: xy(2, 5), bd(2, 5)
  integer(c_int32_t) :: cells(3, 4), edge(2, 1), patch(1)

  xy = reshape([0d0, 0d0, 1d0, 0d0, 1d0, 1d0, 0d0, 1d0, 0.5d0, 0.5d0], [2, 5])
  cells = reshape([1, 2, 5, 2, 3, 5, 3, 4, 5, 4, 1, 5], [3, 4])   ! 1-based
  edge = reshape([2, 3], [2, 1])                                   ! the right edge is patch 2
  patch = [2]
  bd = 0
  bd(2, 3) = 0.1d0   ! both top corners rise by 0.1; every other boundary vertex stays
  bd(2, 4) = 0.1d0

  call mesh%create_triangles(xy, cells, edge, patch)
  call bcs%create()
  call solver%create(mesh, bcs)
  call solver%move(bd, xy)
  print '(a, 2f8.4, a)', "consumer (Fortran): centre moved to (", xy(:, 5), ")"
  call solver%free()
  call bcs%free()
  call mesh%free()
  if (xy(2, 5) <= 0.5d0) error stop "the centre did not rise"
end program
