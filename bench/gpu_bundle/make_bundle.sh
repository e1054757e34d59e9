#!/usr/bin/env bash
# Packs what the Vulkan twins' checks need to run on a machine that has a GPU driver but none of
# cutwork's Debian packages: the stripped cutwork, cutwork-bench and cutwork_gpu_tests of a build,
# the shared libraries they load (glibc, libstdc++ and libgcc_s left to the machine: newer ones read
# these binaries), and the Khronos validation layer the GPU tests switch on. One xz tarball (about
# 35 MB from 150 MB) beside run.sh, which unpacks and runs it there.
#   bash bench/gpu_bundle/make_bundle.sh BUILD_DIR OUT_DIR
set -euo pipefail
build=${1:?build directory}
out=${2:?output directory}
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/lib" "$stage/layers" "$out"
for b in cutwork cutwork-bench cutwork_gpu_tests; do strip -o "$stage/$b" "$build/bin/$b"; done
# The GPU tests read their data and the cutwork executable at the paths of this build.
{
  sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt"
  (cd "$build/bin" && pwd)
} > "$stage/built_at"
for b in cutwork cutwork-bench cutwork_gpu_tests; do ldd "$build/bin/$b"; done | awk '/=>/ {print $3}' | sort -u |
  while read -r lib; do
    case $(basename "$lib") in
      libc.so*|libm.so*|libpthread*|libdl.so*|librt.so*|ld-linux*|libstdc++*|libgcc_s*) ;;
      *) cp -L "$lib" "$stage/lib/" ;;
    esac
  done
layer=/usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json
if [ -f "$layer" ]; then
  cp "$layer" "$stage/layers/"
  cp -L /usr/lib/x86_64-linux-gnu/libVkLayer_khronos_validation.so "$stage/lib/"
fi
tar -C "$stage" -cf - . | xz -T2 -6 > "$out/bundle.tar.xz"
cp "$(dirname "$0")/run.sh" "$out/run.sh"
ls -la "$out"
