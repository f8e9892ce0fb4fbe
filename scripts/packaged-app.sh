#!/usr/bin/env bash
# Proves aograph's library crates work from a registry: packages them (`cargo package`, as
# `cargo publish` would), unpacks the .crate files outside the repository, builds a small
# application (.ci/packaged-app) that depends on aograph-embed through them only (a [patch]
# to the unpacked folders, no path into this repository), deletes the unpacked sources, and
# runs the application on a Vulkan device from another directory. A shader a crate did not
# embed fails the run by name; nothing may be read from the source tree.
#
# Usage: bash scripts/packaged-app.sh [work-dir]   (default: a new temporary directory)
set -euo pipefail
cd "$(dirname "$0")/.."
repo="$PWD"
work="${1:-$(mktemp -d)}"
mkdir -p "$work"
# The library crates, in dependency order (the application needs the first six; the rest
# must package too).
crates=(aograph-shaders aograph-graph aograph-frame aograph-ao-passes aograph-scene aograph-tracing aograph-embed aograph-renderer aograph-app-config aograph-bench)
args=()
for c in "${crates[@]}"; do args+=(-p "$c"); done
# --no-verify: the application's build below compiles the packaged sources instead.
cargo package --locked --no-verify --quiet "${args[@]}"
rm -rf "$work/crates" "$work/app"
mkdir -p "$work/crates" "$work/app/src"
for c in "${crates[@]}"; do
    file="target/package/$c-0.1.0.crate"
    tar -xzf "$file" -C "$work/crates"
    # Every .wgsl file of the repository's shaders/ must be in the shader crate's package.
    if [ "$c" = aograph-shaders ]; then
        missing=$(cd shaders && find . -name '*.wgsl' | sed 's|^\./||' | while read -r f; do
            [ -f "$work/crates/$c-0.1.0/$f" ] || echo "$f"; done)
        if [ -n "$missing" ]; then
            echo "packaged-app: aograph-shaders' package lacks: $missing" >&2
            exit 1
        fi
    fi
done
cp .ci/packaged-app/src/main.rs "$work/app/src/main.rs"
{
    cat .ci/packaged-app/Cargo.toml.in
    echo
    echo "[patch.crates-io]"
    for c in "${crates[@]}"; do echo "$c = { path = \"../crates/$c-0.1.0\" }"; done
    # The workspace's profiles, so the dependencies built for the workspace are reused.
    echo
    sed -n '/^\[profile\./,$p' Cargo.toml
} > "$work/app/Cargo.toml"
# The workspace's lock pins the same dependency versions.
cp Cargo.lock "$work/app/Cargo.lock"
if grep -rn "$repo" "$work/app/Cargo.toml"; then
    echo "packaged-app: the application names the repository" >&2
    exit 1
fi
(cd "$work/app" && CARGO_TARGET_DIR="$repo/target" cargo build --quiet --bin aograph-packaged-app)
# The unpacked sources (shaders included) are gone before the application runs: what it runs
# was compiled in. No development override either.
rm -rf "$work/crates"
mkdir -p "$work/run"
(cd "$work/run" && env -u AOGRAPH_SHADERS "$repo/target/debug/aograph-packaged-app")
