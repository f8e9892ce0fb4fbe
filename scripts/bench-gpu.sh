#!/usr/bin/env bash
# The full benchmark for a GPU (or any device): builds in release and runs `aograph bench` with
# every technique at every preset (configs/sweeps/presets.toml), at 1920x1080 and 1280x720,
# with the roofline (the device's own load and byte peaks, every pass's share of them), into
# one results folder: <out>/<width>x<height>/{report.md,results.csv,results.json,pareto.*}
# and <out>/device.txt.
#
# Then rtao converged: 1, 2, 4 and 8 rays a frame accumulated over 64 frames
# (<out>/<size>-rtao-converged); rtao's denoisers scored on every frame after a reset
# (<out>/<size>-rtao-denoisers, configs/sweeps/rtao-denoisers.toml, the compute or hardware
# backend as `auto` picks); on both backends of the ray tracer where the device has ray
# queries (configs/sweeps/ray-tracers.toml; the compute backend only otherwise), and the CPU,
# compute and hardware tracers in rays per second (<out>/ray-throughput.txt, criterion's
# reference bench).
#
#   bash scripts/bench-gpu.sh [OUT]            # default OUT: bench-gpu
#   SIZES="96x64" FRAMES=1 WARMUP=0 RAYS=4 SCENES=columns PROFILE=debug RTAO_FRAMES=1 \
#       bash scripts/bench-gpu.sh out      # a smoke run (CI: the debug build it already has)
#
# On lavapipe (no GPU) the times are CPU times; on a GPU, AOGRAPH_TIMING=gpu is the default
# (GPU timestamps), and the report names the device.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-bench-gpu}
sizes=${SIZES:-"1920x1080 1280x720"}
frames=${FRAMES:-8}
warmup=${WARMUP:-2}
rays=${RAYS:-256}
scenes=${SCENES:-columns,sphere-on-plane,corner}
profile=${PROFILE:-release}
rtao_frames=${RTAO_FRAMES:-62}
bash scripts/ensure-vulkan.sh
if [ "$profile" = release ]; then
    cargo build --release --locked --quiet
else
    cargo build --locked --quiet
fi
mkdir -p "$out"
# Which backends rtao can take here: `aograph render` says which one `tracer = "auto"` chose.
rtao_sweep=configs/sweeps/presets.toml
probe=$("./target/$profile/aograph" render --config configs/rtao.toml --width 8 --height 8 \
    --frames 1 --out "$out/tracer-probe")
if grep -q "^ray tracer: hardware" <<<"$probe"; then
    rtao_sweep=configs/sweeps/ray-tracers.toml
fi
rm -rf "$out/tracer-probe"
{
    echo "aograph bench-gpu, $(date -u +%Y-%m-%dT%H:%M:%SZ)"
    echo "sizes: $sizes; scenes: $scenes; frames $frames after $warmup warm-up; reference $rays rays"
    echo "rtao sweep: $rtao_sweep"
    command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader || true
} > "$out/device.txt"
for size in $sizes; do
    w=${size%x*}
    h=${size#*x}
    "./target/$profile/aograph" bench \
        --scenes "$scenes" --techniques all --sweep configs/sweeps/presets.toml \
        --width "$w" --height "$h" --frames "$frames" --warmup "$warmup" --rays "$rays" \
        --quiet --out "$out/$size"
    grep -m1 "^Device:" "$out/$size/report.md" >> "$out/device.txt"
    "./target/$profile/aograph" bench \
        --scenes "$scenes" --techniques rtao --sweep "$rtao_sweep" \
        --width "$w" --height "$h" --frames "$rtao_frames" --warmup 2 --rays "$rays" \
        --quiet --out "$out/$size-rtao-converged"
    # rtao's denoisers frame by frame after a reset, as many frames as the converged run
    # renders (its warm-up included). The converged run's report.md has the history
    # denoiser's history_fix and atrous passes' ms at this size; these include cold frames.
    "./target/$profile/aograph" bench \
        --scenes "$scenes" --sweep configs/sweeps/rtao-denoisers.toml \
        --width "$w" --height "$h" --convergence "$((rtao_frames + 2))" --rays "$rays" \
        --quiet --out "$out/$size-rtao-denoisers"
done
if [ "$profile" = release ]; then
    cargo bench --locked -p aograph-scene --bench reference -- reference/ 2>&1 \
        | grep -E "^reference|thrpt" > "$out/ray-throughput.txt" || true
    cargo bench --locked -p aograph-scene --bench reference -- ray_batch 2>&1 \
        | grep -E "^ray_batch|thrpt" >> "$out/ray-throughput.txt" || true
fi
echo "bench-gpu: wrote $out/ ($(echo $sizes | wc -w) sizes)"
