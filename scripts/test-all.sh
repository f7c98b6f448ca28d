#!/usr/bin/env bash
# Builds everything and runs every test. `.ci/run` runs exactly this.
#   rustfmt, clippy (all targets, warnings are errors) and rustdoc (warnings are errors); Rust
#   library and tests, header freshness (tests/header_fresh.rs), CMake build of the C and Fortran
#   examples into build/, cargo test and ctest (examples vs the Rust reference, the C bad-input
#   test under valgrind, install + C and Fortran consumers by find_package, pkg-config and plain
#   compiler flags, code_saturne moving its mesh with meshmove); the distributed build (the
#   `mpi` feature: clippy, its tests and the paper's cases under mpirun on 1 to 4 ranks against
#   the serial solver, rustdoc; the command line's `deform` under mpirun against the serial
#   command; the C and Fortran programs on 1 to 4 ranks; code_saturne on 2 and 4 ranks).
set -euo pipefail
cd "$(dirname "$0")/.."

# cmake, gfortran, valgrind and pkg-config, for the distributed build (the `mpi` feature)
# OpenMPI and libclang (rsmpi generates its bindings with bindgen), and code_saturne with its
# Fortran modules for the example that moves code_saturne's mesh (examples/code_saturne):
# installed when missing (CI runs as root on Debian/Ubuntu).
missing=()
for tool in cmake gfortran valgrind pkg-config; do
    command -v "$tool" >/dev/null 2>&1 || missing+=("$tool")
done
for pkg in libopenmpi-dev openmpi-bin libclang-dev code-saturne code-saturne-include; do
    dpkg -s "$pkg" >/dev/null 2>&1 || missing+=("$pkg")
done
if ((${#missing[@]})); then
    echo "installing ${missing[*]}"
    SUDO=""
    [ "$(id -u)" -ne 0 ] && SUDO="sudo"
    $SUDO apt-get update -qq
    $SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" >/dev/null
fi

# code_saturne's run script needs USER, which containers often leave unset.
export USER="${USER:-$(id -un)}"

# clippy and rustfmt: rustup components, added when missing.
for component in clippy rustfmt; do
    if ! cargo "${component/rustfmt/fmt}" --version >/dev/null 2>&1; then
        rustup component add "$component"
    fi
done
cargo fmt --check
cargo clippy --release --all-targets -- -D warnings

cargo build --release --all-targets
# The committed header must match what cbindgen generates from src/capi.
cargo test --release --test header_fresh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DMESHMOVE_WITH_CLI=ON
cmake --build build -j "$(nproc)"
cargo test --release
(cd build && ctest --output-on-failure -j "$(nproc)")
# The library alone, as a user builds it, linted with and without the `mpi` feature (the
# workspace above turns on `internals`); the distributed tests, which run themselves under
# mpirun on 1 to 4 ranks, the library's and the cases':
# tests/distributed.rs (every method and condition, the steps, the faults),
# tests/distributed_ghosts.rs (parts with all, some or none of their ghost cells) and
# cases/tests/distributed.rs (the paper's cases, SLIP walls, periodic links across ranks, split
# interfaces, the wall-layered airfoil and wing, against the serial solver to 1e-10 of the
# motion).
cargo clippy --release -p meshmove -- -D warnings
cargo clippy --release -p meshmove --features mpi -- -D warnings
cargo clippy --release -p meshmove --all-targets --features mpi,internals -- -D warnings
cargo test --release --features mpi -p meshmove -p meshmove-cases --test distributed --test distributed_ghosts
# The command line under mpirun (its `mpi` feature: METIS's partition, the parts, `deform`
# against the serial command on 1 to 4 ranks: cli/tests/deform_mpi.rs).
cargo clippy --release -p meshmove-cli --all-targets --features mpi -- -D warnings
cargo test --release -p meshmove-cli --features mpi --bin meshmove distributed
cargo test --release -p meshmove-cli --features mpi --test deform_mpi
# The C and Fortran programs of the distributed calls under mpirun on 1 to 4 ranks, and
# code_saturne moving its mesh on 1, 2 and 4 ranks with them (examples/code_saturne): a second
# CMake build with MESHMOVE_WITH_MPI (its own cargo target directory, kept between runs), of
# those programs alone.
cmake -S . -B build-mpi -DCMAKE_BUILD_TYPE=Release -DMESHMOVE_WITH_MPI=ON
mpi_targets=(fv_body3d_mpi_c free_surface_mpi_f)
command -v code_saturne >/dev/null 2>&1 && mpi_targets+=(code_saturne_check)
cmake --build build-mpi -j "$(nproc)" --target "${mpi_targets[@]}"
(cd build-mpi && ctest --output-on-failure -R '_mpi_(c|f)_np|^code_saturne_')
# The API documentation builds without a warning (broken links, bad markup).
RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps
RUSTDOCFLAGS="-D warnings" cargo doc --release --no-deps -p meshmove --features mpi
