#!/usr/bin/env bash
# GPU against CPU speed (closest hits, all crossings) on Russig's bundle, 10⁵ to 10⁸ links (as memory allows):
# run unchanged on a machine with a Vulkan GPU. On Mesa's lavapipe the GPU column measures the
# CPU emulating a GPU. Override the sizes with TUBECAST_GPU_BENCH_LINKS=10000,100000.
# Where Embree 3 is installed (Debian: libembree-dev), the lab's `gpu` report then puts the GPU
# beside the CPU path and Embree on the same rays, into ${OUT:-target/gpu-report}/gpu.md.
set -euo pipefail
cd "$(dirname "$0")/../.."
export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-/tmp/xdg-runtime-$(id -u)}"
mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
export TUBECAST_GPU_BENCH_LINKS="${TUBECAST_GPU_BENCH_LINKS:-100000,1000000,10000000,100000000}"
cargo bench -p tubecast-gpu --bench gpu
if [ -e /usr/include/embree3/rtcore.h ] || ldconfig -p 2>/dev/null | grep -q libembree3; then
  cargo run --release -p tubecast-lab --features embree,gpu -- gpu --quiet --out "${OUT:-target/gpu-report}"
else
  echo "bench.sh: Embree 3 not found (apt-get install libembree-dev): the lab's gpu report was not run" >&2
fi
