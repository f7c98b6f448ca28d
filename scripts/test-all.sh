#!/usr/bin/env bash
# Builds everything and runs every test. `.ci/run` runs exactly this.
set -euo pipefail
cd "$(dirname "$0")/.."

cargo build --release --all-targets
cargo test --release
