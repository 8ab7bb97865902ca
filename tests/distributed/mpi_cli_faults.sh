#!/usr/bin/env bash
# The CLI under `mpirun -np 2` (docs/mpi.md): a distributed reference is byte-identical to the single-process one;
# bad input ends the job with exit 2 and one line naming it; a rank killed mid-run ends the whole job within
# seconds, non-zero, leaving a valid checkpoint that resumes on another rank count.
# Usage: mpi_cli_faults.sh CLRADIOSITY MPIRUN SCENES_DIR
set -uo pipefail
cli=$(realpath "$1") mpirun=$2 scenes=$3
scene=$scenes/cornell-box.xml
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
two() { "$mpirun" -n 2 "$cli" "$@"; }
# The pid of rank $1 among the children of mpirun's process $job.
rank_pid() {
  for pid in $(pgrep -P $job); do
    tr '\0' '\n' <"/proc/$pid/environ" 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$1" && { echo "$pid"; return; }
  done
}
# Waits up to $1 s for mpirun's process $job to end after $2 (what happened, for the messages); past that continues
# $3 (a stopped rank, or nothing), kills the job and fails. Sets rc to the job's exit status.
await_end() {
  local limit=$1 after=$2 held=${3:-} start=$SECONDS
  for _ in $(seq $((limit * 10))); do kill -0 $job 2>/dev/null || break; sleep 0.1; done
  if kill -0 $job 2>/dev/null; then
    [ -n "$held" ] && kill -CONT "$held"
    kill -9 $job
    fail "the job still runs $limit s after $after"
  fi
  wait $job
  rc=$?
  echo "job ended $((SECONDS - start)) s after $after, exit $rc"
}
# Starts a 2-rank training into $work/$1 in the background (its output in $work/$1.out; mpirun options after the
# name), sets $job and waits until its log holds $2 lines.
train_two() {
  local name=$1 rows=$2
  shift 2
  "$mpirun" "$@" -n 2 "$cli" train "$scene" --config "$work/small.json" --steps 1000000 -o "$work/$name" \
    >"$work/$name.out" 2>&1 &
  job=$!
  for _ in $(seq 600); do
    [ "$(cat "$work/$name/log.csv" 2>/dev/null | grep -c .)" -ge "$rows" ] && return
    kill -0 $job 2>/dev/null || fail "the 2-rank training ended early: $(tail -3 "$work/$name.out")"
    sleep 0.1
  done
}

echo "== distributed reference equals the single-process image"
"$cli" reference "$scene" --spp 4 --width 40 --height 31 --seed 5 -o "$work/one.exr" >/dev/null 2>&1 ||
  fail "single-process reference"
two reference "$scene" --spp 4 --width 40 --height 31 --seed 5 -o "$work/two.exr" >/dev/null 2>&1 ||
  fail "2-rank reference"
# The pixels, not the bytes: each EXR's header records its own command line and render time.
"$cli" compare "$work/one.exr" "$work/two.exr" --json | grep -q '"mse":0.0,' ||
  fail "the 2-rank image differs from the 1-rank one"

echo "== a rank still computing is slow, not lost: a reference longer on one rank than the timeout completes"
# Rank 1 is held back 3 s early in its rows (SIGSTOP, then SIGCONT): rank 0 finishes first and waits in the gather
# for seconds past the 1 s timeout, taking roll calls; rank 1 answers between its passes that it is computing, and
# when it arrives in the gather the collective completes rather than being taken for ranks in different
# collectives (what a long reference on one rank was ended as before).
CLRADIOSITY_MPI_TIMEOUT=1 "$mpirun" -x CLRADIOSITY_MPI_TIMEOUT -n 2 "$cli" reference "$scene" --spp 1200 --width 128 \
  --height 128 -o "$work/slow.exr" >"$work/slow.out" 2>&1 &
job=$!
slow=""
for _ in $(seq 100); do
  slow=$(rank_pid 1)
  [ -n "$slow" ] && break
  sleep 0.05
done
[ -n "$slow" ] || { kill $job; fail "rank 1 not found among mpirun's children"; }
sleep 0.5
kill -STOP "$slow"
sleep 3
kill -CONT "$slow"
wait $job || fail "a slow rank ended the job: $(grep clradiosity "$work/slow.out" | head -3)"
[ -f "$work/slow.exr" ] || fail "no image from the job with a slow rank"

echo "== bad input ends the job with exit 2 and names the culprit"
start=$SECONDS
two train "$work/missing.xml" --steps 5 -o "$work/bad" >"$work/bad.out" 2>&1
rc=$?
[ "$rc" -eq 2 ] || fail "exit $rc for a missing scene, want 2"
grep -q "clradiosity: error: rank [01]: .*missing.xml" "$work/bad.out" || fail "no error line naming the scene"
[ $((SECONDS - start)) -lt 30 ] || fail "bad input took $((SECONDS - start)) s to end the job"

echo "== a bad CLRADIOSITY_MPI_TIMEOUT ends every rank with exit 2 and one line, whatever command reads it first"
# The value is read in the first collective, whose buffers MPI still owns until it completes: refusing it before
# then corrupted the heap (an abort in MPI_Finalize, exit 134).
for value in abc nan -5 0.5 5s 1e400; do
  for command in "train $scene --steps 2 --batch 64 -o $work/timeout" "reference $scene --spp 1 --width 8 --height 8 -o $work/timeout.exr"; do
    rm -rf "$work/timeout" "$work/timeout.exr"
    CLRADIOSITY_MPI_TIMEOUT=$value "$mpirun" -x CLRADIOSITY_MPI_TIMEOUT -n 2 "$cli" $command >"$work/timeout.out" 2>&1
    rc=$?
    [ "$rc" -eq 2 ] || fail "exit $rc for CLRADIOSITY_MPI_TIMEOUT='$value' ($command), want 2: $(head -3 "$work/timeout.out")"
    [ "$(grep -c "clradiosity: error: CLRADIOSITY_MPI_TIMEOUT '$value'" "$work/timeout.out")" -eq 1 ] ||
      fail "not one line naming CLRADIOSITY_MPI_TIMEOUT='$value': $(head -3 "$work/timeout.out")"
    [ ! -e "$work/timeout" ] && [ ! -e "$work/timeout.exr" ] || fail "output left behind for a refused timeout"
  done
done

echo "== a rank killed mid-run ends the job within seconds; the checkpoint resumes on one rank"
cat >"$work/small.json" <<'EOF'
{"log_every": 2, "checkpoint_every": 4, "batch": 256,
 "network": {"width": 64, "hidden_layers": 2,
             "encoder": {"grid": {"levels": 6, "log2_table": 14, "base_resolution": 4}}}}
EOF
train_two run 4
[ -f "$work/run/model.clr" ] || fail "no checkpoint after 60 s: $(tail -3 "$work/run.out")"
victim=$(rank_pid 1)
[ -n "$victim" ] || { kill $job; fail "rank 1 not found among mpirun's children"; }
kill -9 "$victim"
await_end 30 "rank 1 was killed"
[ "$rc" -ne 0 ] || fail "exit 0 after a rank died"
steps=$(tail -1 "$work/run/log.csv" | cut -d, -f1)
"$cli" train "$scene" --resume --steps $((steps + 6)) -o "$work/run" >"$work/resume.out" 2>&1 ||
  fail "resume on one rank: $(tail -2 "$work/resume.out")"
grep -q "^$((steps + 6))," "$work/run/log.csv" || fail "the resumed run logged no step $((steps + 6))"
echo "== ranks given different work stop before it, with one line naming the rank"
for variant in "--spp 4:--spp 8" "--spp 4 --seed 1:--spp 4 --seed 2"; do
  "$mpirun" -n 1 "$cli" reference "$scene" --width 8 --height 8 ${variant%%:*} -o "$work/mixed.exr" : \
    -n 1 "$cli" reference "$scene" --width 8 --height 8 ${variant##*:} -o "$work/mixed.exr" >"$work/mixed.out" 2>&1
  rc=$?
  [ "$rc" -eq 2 ] || fail "exit $rc for ranks given $variant, want 2: $(head -3 "$work/mixed.out")"
  [ "$(grep -c "clradiosity: error" "$work/mixed.out")" -eq 1 ] || fail "not one error line: $(cat "$work/mixed.out")"
  grep -q "clradiosity: error: rank 1 was given other work than rank 0: the command lines differ" "$work/mixed.out" ||
    fail "no line naming rank 1: $(head -3 "$work/mixed.out")"
  [ ! -e "$work/mixed.exr" ] || fail "an image was written from mixed work"
done
# The same command line on another copy of the scene's folder with a changed file: the scene's contents differ.
mkdir -p "$work/a" "$work/b"
cp "$scene" "$work/a/scene.xml"
sed 's/0.63, 0.065, 0.05/0.6, 0.065, 0.05/' "$scene" >"$work/b/scene.xml"
cmp -s "$work/a/scene.xml" "$work/b/scene.xml" && fail "the scene edit changed nothing"
# The same command line (a relative path) in two working folders: only the scenes' contents differ.
"$mpirun" -n 1 -wdir "$work/a" "$cli" reference scene.xml --width 8 --height 8 --spp 1 -o mixed.exr : \
  -n 1 -wdir "$work/b" "$cli" reference scene.xml --width 8 --height 8 --spp 1 -o mixed.exr >"$work/scenes.out" 2>&1
rc=$?
[ "$rc" -eq 2 ] || fail "exit $rc for ranks given different scenes, want 2: $(head -3 "$work/scenes.out")"
grep -q "clradiosity: error: rank 1 was given other work than rank 0: the scenes" "$work/scenes.out" ||
  fail "no line naming the scenes: $(head -3 "$work/scenes.out")"
[ ! -e "$work/a/mixed.exr" ] || fail "an image was written from different scenes"

echo "== a command that does not use MPI is refused under mpirun"
two render "$scene" --model "$work/run" -o "$work/r.exr" >"$work/render.out" 2>&1
rc=$?
[ "$rc" -eq 2 ] || fail "exit $rc for render under mpirun, want 2"
[ "$(grep -c "clradiosity: error" "$work/render.out")" -eq 1 ] || fail "not one line: $(cat "$work/render.out")"
grep -q "render runs in one process" "$work/render.out" || fail "no line naming render: $(cat "$work/render.out")"

echo "== a stop signal that finds a rank waiting for another ends the job within seconds, the checkpoint kept"
# Rank 1 is held (SIGSTOP), so rank 0 waits in a step's collective that cannot complete; SIGTERM to rank 0 must end
# the job within about a second (not after the 300 s collective timeout), with exit 143 and one line.
train_two sigwait 3
held=$(rank_pid 1) waiting=$(rank_pid 0)
[ -n "$held" ] && [ -n "$waiting" ] || { kill $job; fail "ranks 0 and 1 not found among mpirun's children"; }
kill -STOP "$held"
sleep 1
kill -TERM "$waiting"
await_end 20 "SIGTERM reached the waiting rank" "$held"
[ "$rc" -eq 143 ] || fail "exit $rc after SIGTERM, want 143: $(grep clradiosity "$work/sigwait.out" | head -3)"
grep -q "clradiosity: stopped: rank 0: stopped by SIGTERM while waiting in .*the other ranks did not arrive within 1 s" \
  "$work/sigwait.out" || fail "no line saying why: $(grep clradiosity "$work/sigwait.out" | head -3)"
[ -s "$work/sigwait/model.clr" ] || fail "no checkpoint kept"

echo "== a rank that stops answering ends the job after the collective timeout, naming it"
CLRADIOSITY_MPI_TIMEOUT=5 train_two stopped 3 -x CLRADIOSITY_MPI_TIMEOUT
victim=$(rank_pid 1)
[ -n "$victim" ] || { kill $job; fail "rank 1 not found among mpirun's children"; }
kill -STOP "$victim"
await_end 60 "rank 1 stopped (timeout 5 s, 30 s to answer the roll call)" "$victim"
[ "$rc" -ne 0 ] || fail "exit 0 after a rank stopped answering"
grep -q "clradiosity: failed: rank 0: .* did not complete within 5 s: rank 1 did not answer within 30 s" \
  "$work/stopped.out" ||
  fail "no line naming rank 1: $(grep clradiosity "$work/stopped.out" | head -3)"
echo "PASS"
