#!/usr/bin/env bash
# The paper's tables regenerated (ISNR §5, Tables 1, 2 and 4, Fig. 3), side by side with its own numbers
# (bench/paper/paper.json), and the path tracer's error against seconds beside the trainings' (time to quality).
#
#   bench/paper_tables.sh [DEVICE] OUT_DIR SCENE...
#
# SCENE is a scene folder (SCENE/scene.xml) or a scene file. DEVICE is a --device SPEC (default: CLRADIOSITY_DEVICE,
# else the default rule). For every scene and table (TABLES, default "1 2": N = 4 and N = 32) it trains, with
# `--preset paper` and convergence logging (`train --reference --eval-every`):
#   Table 1 (N = 4): nr, isnr with kl and isnr with ikl, at the paper's step count for the scene (the ablation,
#                    Table 4, reads their evaluations at 4k/10k/20k/30k steps);
#   Table 2 (N = 32): nr and isnr (ikl), each at the paper's own step count (ISNR's is about half).
# A scene the paper does not show takes the preset's default budget for every run. The reference is the scene's
# TungstenRender.exr when it has the evaluation size, else path-traced by `clradiosity reference` at REF_SPP
# (cached in OUT_DIR/references). The path tracer's points (doubling spp from 1, seed 2: independent of the
# reference's) go on until they reach the best model's MAPE or PT_MAX_SECONDS. Then bench/paper_tables.py writes
# OUT_DIR/tables.md and OUT_DIR/<scene>-curves.svg. Every step is cached: a rerun continues (a finished run is kept,
# an interrupted one resumes).
#
# Environment (defaults in brackets): CLRADIOSITY [build/release/clradiosity]; TABLES ["1 2"]; PRESET [paper]
# (empty: the device's defaults, the CPU scale); STEPS (every run's step count instead of the paper's); EVAL_EVERY
# [1000: divides the ablation's steps]; EVAL_SPP [4, as `render`]; EVAL_LONG_SIDE [512, the paper's resolution: the
# film scaled to it, never up]; REF_SPP [32768, the paper's references]; PT_MAX_SECONDS [the longest training of
# the scene]; TRAIN_FLAGS (more `train` flags, e.g. "--batch 4096"). A tiny smoke test:
#   STEPS=40 EVAL_EVERY=20 EVAL_LONG_SIDE=32 REF_SPP=64 TABLES=1 PRESET= bench/paper_tables.sh /tmp/p scenes/cornell-box.xml
set -euo pipefail

usage() {
  sed -n '5p' "$0" | sed 's/^# *//' >&2
  exit 2
}
is_scene() { [ -f "$1/scene.xml" ] || [[ "$1" == *.xml && -f "$1" ]]; }
[ $# -ge 2 ] || usage
if is_scene "$2"; then
  device=${CLRADIOSITY_DEVICE:-} out=$1
  shift 1
else
  [ $# -ge 3 ] || usage
  device=$1 out=$2
  shift 2
fi
[ -n "$device" ] && export CLRADIOSITY_DEVICE=$device
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${CLRADIOSITY:-$root/build/release/clradiosity}
[ -x "$bin" ] || {
  echo "paper_tables.sh: $bin is not built (CLRADIOSITY names another binary)" >&2
  exit 2
}
tables=${TABLES:-1 2}
for t in $tables; do case $t in 1 | 2) ;; *)
  echo "paper_tables.sh: TABLES: '$t' is not 1 or 2" >&2
  exit 2
  ;;
esac; done
preset=${PRESET-paper}
eval_every=${EVAL_EVERY:-1000}
eval_spp=${EVAL_SPP:-4}
long_side=${EVAL_LONG_SIDE:-512}
ref_spp=${REF_SPP:-32768}
read -r -a train_flags <<<"${TRAIN_FLAGS:-}"
paper_json=$root/bench/paper/paper.json
for s in "$@"; do is_scene "$s" || {
  echo "paper_tables.sh: $s: not a scene (a folder with scene.xml, or an .xml file)" >&2
  exit 2
}; done
mkdir -p "$out"/references "$out"/runs "$out"/path_tracer
out=$(cd "$out" && pwd)

# pyjson FILE [--default VALUE] KEY...: the value at KEY... of a JSON file (python3's json: no other dependency).
# The keys are data, never code: a scene named with a quote (or crafted as Python) is only a key.
pyjson() {
  python3 -c '
import json, sys
args = sys.argv[1:]
d = json.load(open(args.pop(0)))
default = None
if args[:1] == ["--default"]:
    default, args = args[1], args[2:]
try:
    for k in args:
        d = d[k]
except (KeyError, IndexError, TypeError):
    if default is None:
        raise
    d = default
print(d)' "$@"
}
# The width and height of an EXR (its dataWindow), read with python3's struct.
exr_size() {
  python3 - "$1" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read(1 << 16)
i = data.index(b"dataWindow\0box2i\0") + len(b"dataWindow\0box2i\0") + 4
x0, y0, x1, y1 = struct.unpack("<4i", data[i:i + 16])
print(x1 - x0 + 1, y1 - y0 + 1)
PY
}

# failed LABEL DIR: a training that exited with an error ends the script, with its last line.
failed() {
  echo "paper_tables.sh: $name $1 failed: $(tail -n 1 "$2.err") (all of it: $2.err)" >&2
  exit 1
}

for s in "$@"; do
  if [ -d "$s" ]; then scene=$s/scene.xml scene_dir=$s; else scene=$s scene_dir=$(dirname "$s"); fi
  name=$(basename "$scene_dir")
  [ "$(basename "$scene")" = scene.xml ] || name=$(basename "$scene" .xml)
  tungsten=$scene_dir/TungstenRender.exr
  # The film's size: Tungsten's render is made at it; else a 1-spp render at the film shows it.
  if [ -f "$tungsten" ]; then
    read -r film_w film_h < <(exr_size "$tungsten")
  else
    "$bin" reference "$scene" --spp 1 -o "$out/references/$name-film.exr" >/dev/null
    read -r film_w film_h < <(exr_size "$out/references/$name-film.exr")
  fi
  # The evaluation size: the film with its longer side at EVAL_LONG_SIDE (never enlarged), where the aspect ratio
  # stays exact in whole pixels; else the film's own size.
  w=$film_w h=$film_h
  if [ "$film_w" -ge "$film_h" ] && [ "$film_w" -gt "$long_side" ]; then
    w=$long_side h=$((film_h * long_side / film_w))
  elif [ "$film_h" -gt "$film_w" ] && [ "$film_h" -gt "$long_side" ]; then
    h=$long_side w=$((film_w * long_side / film_h))
  fi
  [ $((w * film_h)) -eq $((h * film_w)) ] || w=$film_w h=$film_h
  if [ -f "$tungsten" ] && [ "$w" -eq "$film_w" ] && [ "$h" -eq "$film_h" ]; then
    ref=$tungsten
    ref_note="TungstenRender.exr (${w}x${h})"
  else
    ref=$out/references/$name-${w}x${h}-${ref_spp}spp.exr
    ref_note="path-traced by clradiosity reference, ${w}x${h}, $ref_spp spp"
    if [ ! -f "$ref" ]; then
      echo "== $name: reference ${w}x${h} at $ref_spp spp"
      "$bin" reference "$scene" --max-depth -1 --spp "$ref_spp" --width "$w" --height "$h" -o "$ref"
    fi
  fi
  echo "== $name: evaluations at ${w}x${h}, $eval_spp spp, every $eval_every steps against $ref_note"
  paper_name=$(pyjson "$paper_json" --default "" scenes "$name")
  mkdir -p "$out/runs/$name"
  # Written by json.dumps: a scene path with a quote or a backslash stays one JSON string.
  python3 -c 'import json, sys
a = sys.argv[1:]
print(json.dumps({"scene": a[0], "paper_scene": a[1], "reference": a[2], "width": int(a[3]), "height": int(a[4]),
                  "eval_spp": int(a[5]), "preset": a[6]}))' \
    "$scene" "$paper_name" "$ref_note" "$w" "$h" "$eval_spp" "$preset" >"$out/runs/$name/scene.json"

  # run TABLE METHOD LOSS: one training, fresh or resumed, with its evaluations; its record beside it.
  run() {
    local table=$1 method=$2 loss=$3 samples steps key
    samples=$(pyjson "$paper_json" "table$table" samples)
    key=$([ "$method" = nr ] && echo nr || echo isnr)
    if [ -n "${STEPS:-}" ]; then
      steps=$STEPS
    elif [ -n "$paper_name" ]; then
      steps=$(pyjson "$paper_json" "table$table" rows "$paper_name" "$key" step)
    else
      steps=""  # the preset's budget
    fi
    if [ -z "$steps" ] && [ -z "$preset" ]; then
      echo "paper_tables.sh: $name is not in the paper and PRESET is empty: give STEPS" >&2
      exit 2
    fi
    local label=t$table-$method${loss:+-$loss} dir=$out/runs/$name/t$table-$method${loss:+-$loss}
    local flags=(--method "$method" --samples "$samples" --reference "$ref" --eval-every "$eval_every"
      --eval-spp "$eval_spp")
    [ -n "$loss" ] && flags+=(--is-loss "$loss")
    [ -n "$steps" ] && flags+=(--steps "$steps")
    if [ -f "$dir/run.json" ]; then
      echo "== $name $label: done, kept"
      return
    fi
    if [ -f "$dir/model.clr" ]; then
      echo "== $name $label: resuming"
      [ -n "$steps" ] || flags+=(--steps "$(pyjson "$dir/config.json" steps)")
      "$bin" train "$scene" --resume "${flags[@]}" "${train_flags[@]}" -o "$dir" >"$dir.out" 2>"$dir.err" ||
        failed "$label" "$dir"
    else
      echo "== $name $label: training${steps:+ $steps steps}"
      rm -rf "$dir"
      "$bin" train "$scene" ${preset:+--preset "$preset"} "${flags[@]}" "${train_flags[@]}" -o "$dir" \
        >"$dir.out" 2>"$dir.err" || failed "$label" "$dir"
    fi
    local memory
    memory=$(sed -n 's/^peak device memory: \([0-9.e+]*\) MiB$/\1/p' "$dir.out" | tail -n 1)
    printf '{"table": %d, "method": "%s", "is_loss": "%s", "samples": %d, "peak_device_mib": %s}\n' \
      "$table" "$method" "$loss" "$samples" "${memory:-null}" >"$dir/run.json"
  }
  for t in $tables; do
    case $t in
      1) run 1 nr "" && run 1 isnr kl && run 1 isnr ikl ;;
      2) run 2 nr "" && run 2 isnr ikl ;;
    esac
  done

  # The path tracer's error against its rendering time: 1, 2, 4, … spp until it reaches the best model's MAPE or
  # the next pass would pass the cap.
  pt=$out/path_tracer/$name
  mkdir -p "$pt"
  read -r best_mape longest_s < <(python3 - "$out/runs/$name" <<'PY'
import csv, glob, os, sys
best, longest = float("inf"), 0.0
for log in glob.glob(os.path.join(sys.argv[1], "*", "log.csv")):
    for row in csv.DictReader(open(log)):
        longest = max(longest, float(row["seconds"]))
        if row.get("mape"):
            best = min(best, float(row["mape"]))
print(best, longest)
PY
  )
  cap=${PT_MAX_SECONDS:-$longest_s}
  points=$pt/points.csv
  [ -f "$points" ] || echo "spp,seconds,mape,mse,relmse" >"$points"
  spp=1
  while :; do
    image=$pt/spp$spp.exr
    if ! grep -q "^$spp," "$points"; then
      line=$("$bin" reference "$scene" --max-depth -1 --spp "$spp" --width "$w" --height "$h" --seed 2 -o "$image" | tail -n 1)
      # "OUT: WxH, S spp, T s, …": the render's own time, without loading the scene.
      seconds=$(sed -n 's/.* spp, \([0-9.]*\) s, .*/\1/p' <<<"$line")
      metrics=$("$bin" compare "$image" "$ref" --json)
      printf '%d,%s,%s,%s,%s\n' "$spp" "$seconds" "$(pyjson /dev/stdin mape <<<"$metrics")" \
        "$(pyjson /dev/stdin mse <<<"$metrics")" "$(pyjson /dev/stdin relmse <<<"$metrics")" >>"$points"
    fi
    read -r seconds mape < <(awk -F, -v s="$spp" '$1 == s { print $2, $3 }' "$points")
    echo "== $name: path tracer $spp spp: ${seconds} s, MAPE $mape"
    awk -v m="$mape" -v b="$best_mape" -v s="$seconds" -v c="$cap" 'BEGIN { exit !(m <= b || 2 * s > c) }' && break
    spp=$((spp * 2))
  done
done

python3 "$root/bench/paper_tables.py" "$out" "$paper_json"
