#!/usr/bin/env bash
# Packs what bench/gpu_acceptance.sh needs into one archive for a machine that has a GPU driver but neither network
# nor this project's build dependencies (docs/nvidia.md, "On a bare GPU machine"):
#
#   bench/device/pack.sh [--paper] [BUNDLE]     (default out/device/bundle.tar.xz)
#
# The archive holds the acceptance binaries of BUILD_DIR (default build/ci), stripped, in the build tree's layout,
# every shared library they load except the C runtime's (Embree, OpenEXR, CLBlast, the ICD loader, ...: Debian 12's),
# and the source folder the binaries were built in (they read scenes through that compiled-in path).
# bench/device/run.sh unpacks it there. Needs the binaries built (cmake --workflow --preset ci).
#
# --paper adds the shared scenes of `run.sh --paper` (staircase and veach-ajar from CLR_SHARED_SCENES, default
# ../shared/scenes; their TungstenRender.png left out): the ../shared beside a checkout does not travel to a device
# machine, and the working tree that does is limited to 64 MiB. They add about 20 MB to the archive's 22.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build/ci}
paper=false
if [ "${1:-}" = --paper ]; then
  paper=true
  shift
fi
bundle=${1:-$root/out/device/bundle.tar.xz}
scenes=${CLR_SHARED_SCENES:-$root/../shared/scenes}
paper_scenes=(staircase veach-ajar)
# BINARIES (space-separated) packs fewer: a measurement of `run.sh --exec` that needs the CLI alone travels lighter.
read -r -a binaries <<<"${BINARIES:-clradiosity tests/clr_tests bench/bench_nn bench/bench_guide bench/bench_pipeline}"
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
mkdir -p "$stage/build" "$stage/lib"
for b in "${binaries[@]}"; do
  [ -x "$build/$b" ] || { echo "pack: $build/$b is missing (cmake --workflow --preset ci builds it)" >&2; exit 2; }
  mkdir -p "$stage/build/$(dirname "$b")"
  strip -o "$stage/build/$b" "$build/$b"
done
# Libraries by the loader's own resolution; the C runtime (libc, libm, libstdc++, ...) is the target's, which is
# newer than Debian 12's on the machines seen so far (Ubuntu 24.04).
for b in "${binaries[@]}"; do ldd "$build/$b"; done | awk '/=> \// {print $3}' | sort -u | while read -r lib; do
  case $(basename "$lib") in
    libc.so* | libm.so* | libpthread.so* | libdl.so* | librt.so* | ld-linux* | libstdc++.so* | libgcc_s.so*) ;;
    *) cp -L "$lib" "$stage/lib/" ;;
  esac
done
echo "$root" >"$stage/source_dir"
parts=(build lib source_dir)
if $paper; then
  for s in "${paper_scenes[@]}"; do
    [ -f "$scenes/$s/scene.xml" ] || { echo "pack: no $scenes/$s/scene.xml (CLR_SHARED_SCENES)" >&2; exit 2; }
  done
  mkdir -p "$stage/scenes"
  tar -C "$scenes" -cf - --exclude=TungstenRender.png --exclude=.DS_Store "${paper_scenes[@]}" |
    tar -C "$stage/scenes" -xf -
  chmod -R u+w "$stage/scenes"  # the shared folder is read-only: the trap here, and run.sh, remove the copies
  parts+=(scenes)
fi
mkdir -p "$(dirname "$bundle")"
tar -C "$stage" -cf - "${parts[@]}" | xz -T0 -3 >"$bundle.tmp"
mv "$bundle.tmp" "$bundle"
echo "$bundle: $(du -h "$bundle" | cut -f1)"
