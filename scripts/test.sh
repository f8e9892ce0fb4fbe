#!/usr/bin/env bash
# The test command (README quick start): ensures a Vulkan device (lavapipe where there is no
# GPU), a virtual display for the viewer's tests (Xvfb) and gltfpack for the optimised-glTF
# tests, then runs every test of the workspace. GPU tests skip, saying so, only when no adapter
# exists and AOGRAPH_REQUIRE_GPU is unset; CI sets it so none can skip.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
bash scripts/ensure-xvfb.sh
bash scripts/ensure-gltfpack.sh
cargo test --workspace --locked "$@"
