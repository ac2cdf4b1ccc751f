#!/usr/bin/env bash
# Builds the fuzz preset's file-reader fuzzers and runs each for a while on a scratch copy of its seed corpus (slow: not part of CI).
#
#   scripts/fuzz-readers.sh [-t SECONDS] [-n] [FUZZER...]
#
#   -t SECONDS  how long each fuzzer runs (default $FUZZ_SECONDS, else 60)
#   -n          do not configure or build (the fuzzers in build-fuzz/ are current)
#   FUZZER      run only these (e.g. dicom_fuzzer nrrd_fuzzer); default: every file reader's fuzzer
#   DENTSIM_BUILD_LOCK=FILE  build under `flock FILE` (a machine whose builds take turns)
#
# Needs clang (the `fuzz` preset). Each fuzzer starts from tests/fuzz/corpus/<fuzzer>/ when it exists,
# copied into a scratch folder so that the inputs a run adds never grow the repository. Exits 1 if any
# fuzzer finds a crash, a leak, a timeout or an out-of-memory, naming the input that reproduces it;
# rerun one with `build-fuzz/tests/fuzz/<fuzzer> <input>`. docs/TESTING.md says more.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${FUZZ_SECONDS:-60}"
build_first=1
while getopts "t:nh" opt; do
  case "$opt" in
    t) seconds="$OPTARG" ;;
    n) build_first=0 ;;
    *) sed -n '2,14p' "$0"; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
[[ "$seconds" =~ ^[0-9]+$ && "$seconds" -gt 0 ]] || { echo "fuzz-readers: -t wants whole seconds, not '$seconds'" >&2; exit 2; }

# The readers of files a user hands dentsim (the device parsers' fuzzers are not file readers).
readers=(dicom_fuzzer nrrd_fuzzer nifti_fuzzer stl_fuzzer ply_fuzzer dvol_fuzzer session_fuzzer wav_fuzzer
         json_fuzzer pen_path_fuzzer task_fuzzer)
if [[ $# -gt 0 ]]; then readers=("$@"); fi

# ---- build ----------------------------------------------------------------------------------------
cd "$root"
build=(cmake --build build-fuzz --target "${readers[@]}" -j2)
if [[ -n "${DENTSIM_BUILD_LOCK:-}" ]]; then build=(flock "$DENTSIM_BUILD_LOCK" "${build[@]}"); fi
if [[ $build_first -eq 1 ]]; then
  [[ -f build-fuzz/build.ninja ]] || cmake --preset fuzz >/dev/null
  "${build[@]}"
fi

# ---- run ------------------------------------------------------------------------------------------
scratch="$(mktemp -d /tmp/dentsim-fuzz-readers.XXXXXX)"
found=0
printf '%-16s %10s %8s %8s  %s\n' fuzzer runs cov ft outcome
for fuzzer in "${readers[@]}"; do
  corpus="$scratch/corpus/$fuzzer" artifacts="$scratch/artifacts/$fuzzer/" log="$scratch/$fuzzer.log"
  mkdir -p "$corpus" "$artifacts"
  if [[ -d "tests/fuzz/corpus/$fuzzer" ]]; then cp "tests/fuzz/corpus/$fuzzer"/* "$corpus/"; fi
  # Each input gets 25 s and 2 GB: the readers' own limits are far below, so more is a finding.
  # Leaks are findings too, but for those of the libraries dentsim cannot free (Teem's gzip stream
  # on a damaged file), listed once for the asan tests and these runs alike.
  rc=0
  LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:print_suppressions=0" \
  "build-fuzz/tests/fuzz/$fuzzer" "$corpus" -max_total_time="$seconds" -timeout=25 -rss_limit_mb=2048 \
    -artifact_prefix="$artifacts" -print_final_stats=1 >"$log" 2>&1 &
  pid=$!
  wait "$pid" || rc=$?
  # The fuzzers that read from a path write the input to /tmp/dentsim-<reader>-fuzz-<pid>[.ext] and
  # leave it there; a run of many minutes leaves one each, which go with it.
  rm -rf /tmp/dentsim-*-fuzz-"$pid" /tmp/dentsim-*-fuzz-"$pid".*
  # libFuzzer's last status line: "#RUNS DONE cov: N ft: M ..." (or the line before a crash).
  stats="$(grep -E '^#[0-9]+' "$log" | tail -1 || true)"
  runs="$(sed -nE 's/^#([0-9]+).*/\1/p' <<<"$stats")"
  cov="$(sed -nE 's/.* cov: ([0-9]+).*/\1/p' <<<"$stats")"
  ft="$(sed -nE 's/.* ft: ([0-9]+).*/\1/p' <<<"$stats")"
  if [[ $rc -eq 0 ]]; then
    printf '%-16s %10s %8s %8s  %s\n' "$fuzzer" "${runs:-?}" "${cov:-?}" "${ft:-?}" ok
  else
    found=1
    printf '%-16s %10s %8s %8s  %s\n' "$fuzzer" "${runs:-?}" "${cov:-?}" "${ft:-?}" "FOUND (exit $rc), log: $log"
    for input in "$artifacts"*; do [[ -e "$input" ]] && echo "  reproducer: $input"; done
    grep -m1 -E 'ERROR: (AddressSanitizer|LeakSanitizer|libFuzzer)|runtime error:' "$log" | sed 's/^/  /' || true
  fi
done

# A clean run leaves nothing behind; a finding keeps the scratch folder, reproducers and logs.
if [[ $found -eq 0 ]]; then
  rm -rf "$scratch"
else
  echo "fuzz-readers: findings kept in $scratch" >&2
fi
exit "$found"
