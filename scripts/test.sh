#!/usr/bin/env bash
# The test command (README quick start): ensures a Vulkan device (lavapipe where there is no
# GPU), then runs every test of the workspace. GPU tests skip, saying so, only when no adapter
# exists and AOGRAPH_REQUIRE_GPU is unset; CI sets it so none can skip.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
cargo test --workspace --locked "$@"
