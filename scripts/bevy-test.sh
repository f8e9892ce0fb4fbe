#!/usr/bin/env bash
# aograph-bevy (crates/bevy), which is its own cargo workspace on its own toolchain: bevy 0.20
# needs Rust 1.97.1, and crates/bevy/rust-toolchain.toml pins one that rustup installs here on
# a fresh machine. Formatting, lints, then the tests, the headless bevy app on lavapipe among
# them (scripts/ensure-vulkan.sh makes sure a Vulkan device exists).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/ensure-vulkan.sh
cd crates/bevy
# Installs the toolchain rust-toolchain.toml names when it is missing (no-op otherwise).
rustup toolchain install
cargo fmt --all -- --check
cargo clippy --all-targets --locked -- -D warnings
RUSTDOCFLAGS="-D warnings" cargo doc --no-deps --locked --quiet
cargo test --locked "$@"
# The windowed example builds (it needs a display to run).
cargo clippy --example bevy_ao --features window-example --locked -- -D warnings
echo "bevy-test: toolchain, lints, docs, tests and the windowed example's check took ${SECONDS} s"
