#!/usr/bin/env bash
# Runs a bundle of make_bundle.sh on a machine with a GPU: the GPU tests (validation on), the fill
# ratio and clip kernels' benchmarks beside their TBB twins on the same machine's cores, the
# rasteriser's, and `cutwork design pavilion` on each device. Results into RESULTS_DIR.
#   bash run.sh RESULTS_DIR        (from the repository root: the tests read tests/data)
set -u
results=${1:?results directory}
here=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$results" /tmp/cutwork-bundle && tar -C /tmp/cutwork-bundle -xJf "$here/bundle.tar.xz" || exit 3
export LD_LIBRARY_PATH=/tmp/cutwork-bundle/lib VK_LAYER_PATH=/tmp/cutwork-bundle/layers
for f in /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json /usr/share/vulkan/icd.d/nvidia_icd.json \
  /etc/vulkan/icd.d/nvidia_icd.json; do
  [ -f "$f" ] && export VK_DRIVER_FILES=$f && break
done
echo "ICD: ${VK_DRIVER_FILES:-none found, the loader searches}"; nproc
# The test binary reads its data and the cutwork executable where its build put them: this
# checkout stands in for the source tree there, the bundle's cutwork for the build's.
root=$(sed -n 1p /tmp/cutwork-bundle/built_at)
bin=$(sed -n 2p /tmp/cutwork-bundle/built_at)
[ "$root" != "$PWD" ] && [ ! -e "$root" ] && mkdir -p "$(dirname "$root")" && ln -s "$PWD" "$root"
mkdir -p "$bin" && cp /tmp/cutwork-bundle/cutwork "$bin/"
ldd /tmp/cutwork-bundle/cutwork | grep -i "not found"
export CUTWORK_REQUIRE_VULKAN=1
SECONDS=0; timeout 600 /tmp/cutwork-bundle/cutwork_gpu_tests > "$results/gpu_tests.log" 2>&1
echo "gpu tests: rc $? in ${SECONDS}s"; grep -E "^\[  (PASSED|FAILED|SKIPPED) " "$results/gpu_tests.log"
SECONDS=0
timeout 600 /tmp/cutwork-bundle/cutwork-bench \
  --benchmark_filter='BM_(Clip|Fill|FillRatio)_Tbb|BM_Clip_Vk|BM_ClipFill_Vk|BM_Render' \
  --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \
  --benchmark_out="$results/bench.json" > "$results/bench.log" 2>&1
echo "benchmarks: rc $? in ${SECONDS}s"; grep -E "median" "$results/bench.log"
for d in cpu vulkan; do
  SECONDS=0
  timeout 300 /tmp/cutwork-bundle/cutwork design pavilion --device "$d" --no-render --out "/tmp/cutwork-$d" \
    > "$results/design-$d.log" 2>&1
  echo "design pavilion --device $d: rc $?, ${SECONDS}s"; cp "/tmp/cutwork-$d/report.json" "$results/report-$d.json"
done
