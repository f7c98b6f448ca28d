! A host code's own mesh, as the Fortran examples make it: the structured grid of a box
! [x0,x1]x[y0,y1] of nx x ny squares, two triangles each, and its boundary edges tagged per side;
! the same grid as c_examples/box_grid.h and examples/reference_case.rs, numbered from 1:
!   vertex (i, j), 0 <= i <= nx, 0 <= j <= ny: j (nx + 1) + i + 1, at
!       x = x0 + (x1 - x0) * i / nx,  y = y0 + (y1 - y0) * j / ny
!   square (i, j), corners a = (i, j), b = (i+1, j), c = (i+1, j+1), d = (i, j+1): triangles
!       2 (j nx + i) + 1 = (a, b, c) and 2 (j nx + i) + 2 = (a, c, d), counter-clockwise
!   edges: the bottom side (left to right), the right side (upwards), the top side (left to right),
!       the left side (upwards), on patches side(1:4); a side whose patch is 0 is not tagged.
! make_hex_grid: the box lo..hi in n x n x n hexahedra, as examples/reference_case.rs's hex_grid
! (without a hole) makes it, numbered from 1:
!   vertex (i, j, k), 0 <= i, j, k <= n: (k (n + 1) + j) (n + 1) + i + 1, at lo + (hi - lo) (i, j, k) / n
!   cell (i, j, k): (k n + j) n + i + 1, corners (i,j,k) (i+1,j,k) (i+1,j+1,k) (i,j+1,k) and the same
!       at k+1 (VTK's hexahedron)
!   faces: for each cell in order, each of its faces in VTK's order (z-, z+, y-, x+, y+, x-: corners
!       1 4 3 2, 5 6 7 8, 1 2 6 5, 2 3 7 6, 3 4 8 7, 4 1 5 8, numbered outwards) that lies on the
!       box's boundary, on patch side(face).
module box_grid
  use, intrinsic :: iso_c_binding, only: c_double, c_int32_t
  implicit none (type, external)
  private
  public :: make_box_grid, make_hex_grid

contains

  subroutine make_box_grid(nx, ny, box, side, xy, cells, edges, patches)
    integer, intent(in) :: nx, ny
    real(c_double), intent(in) :: box(4)
    integer(c_int32_t), intent(in) :: side(4)
    real(c_double), allocatable, intent(out) :: xy(:, :)
    integer(c_int32_t), allocatable, intent(out) :: cells(:, :), edges(:, :), patches(:)
    integer :: i, j, k, n, c, f, v, step, nf
    nf = count(side /= 0 .and. [.true., .false., .true., .false.]) * nx + &
      count(side /= 0 .and. [.false., .true., .false., .true.]) * ny
    allocate (xy(2, (nx + 1) * (ny + 1)), cells(3, 2 * nx * ny), edges(2, nf), patches(nf))
    do j = 0, ny
      do i = 0, nx
        xy(1, j * (nx + 1) + i + 1) = box(1) + (box(2) - box(1)) * i / nx
        xy(2, j * (nx + 1) + i + 1) = box(3) + (box(4) - box(3)) * j / ny
      end do
    end do
    c = 0
    do j = 0, ny - 1
      do i = 0, nx - 1
        v = j * (nx + 1) + i + 1
        cells(:, c + 1) = [v, v + 1, v + nx + 2]
        cells(:, c + 2) = [v, v + nx + 2, v + nx + 1]
        c = c + 2
      end do
    end do
    f = 0
    do k = 1, 4
      if (side(k) == 0) cycle
      n = merge(nx, ny, mod(k, 2) == 1)
      step = merge(1, nx + 1, mod(k, 2) == 1)
      do i = 0, n - 1
        select case (k)
        case (1)
          v = i + 1
        case (2)
          v = i * (nx + 1) + nx + 1
        case (3)
          v = ny * (nx + 1) + i + 1
        case default
          v = i * (nx + 1) + 1
        end select
        f = f + 1
        edges(:, f) = [v, v + step]
        patches(f) = side(k)
      end do
    end do
  end subroutine

  subroutine make_hex_grid(n, lo, hi, side, xyz, cells, faces, patches)
    integer, intent(in) :: n
    real(c_double), intent(in) :: lo(3), hi(3)
    integer(c_int32_t), intent(in) :: side(6)
    real(c_double), allocatable, intent(out) :: xyz(:, :)
    integer(c_int32_t), allocatable, intent(out) :: cells(:, :), faces(:, :), patches(:)
    integer, parameter :: hex_face(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, 2, 3, 7, 6, 3, 4, 8, 7, &
      4, 1, 5, 8], [4, 6])
    integer, parameter :: hex_dir(3, 6) = reshape([0, 0, -1, 0, 0, 1, 0, -1, 0, 1, 0, 0, 0, 1, 0, -1, 0, 0], [3, 6])
    integer :: i, j, k, l, c, f, q(3)
    allocate (xyz(3, (n + 1)**3), cells(8, n**3), faces(4, 6 * n * n), patches(6 * n * n))
    do k = 0, n
      do j = 0, n
        do i = 0, n
          xyz(:, vid(i, j, k)) = lo + (hi - lo) * real([i, j, k], c_double) / n
        end do
      end do
    end do
    c = 0
    f = 0
    do k = 0, n - 1
      do j = 0, n - 1
        do i = 0, n - 1
          c = c + 1
          cells(:, c) = [vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k), &
            vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j + 1, k + 1), vid(i, j + 1, k + 1)]
          do l = 1, 6
            q = [i, j, k] + hex_dir(:, l)
            if (all(q >= 0 .and. q < n)) cycle
            f = f + 1
            faces(:, f) = cells(hex_face(:, l), c)
            patches(f) = side(l)
          end do
        end do
      end do
    end do
  contains
    integer(c_int32_t) function vid(i, j, k)
      integer, intent(in) :: i, j, k
      vid = int((k * (n + 1) + j) * (n + 1) + i + 1, c_int32_t)
    end function
  end subroutine
end module box_grid
