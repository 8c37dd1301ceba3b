#!/usr/bin/env bash
# Builds the scene parser's libFuzzer target (tests/fuzz/scene_fuzzer.cpp; Debian's clang,
# -fsanitize=fuzzer,address,undefined) in its own CMake build, MULTIFLUID_FUZZ=ON (the parser and
# what it links, nothing else), then fuzzes it for a bounded time on a copy of the kept corpus
# tests/fuzz/corpus/ (the copy takes the new inputs; the kept corpus is not changed).
# Fails on any crash: a sanitizer report, an exception other than mf::SceneError, a problem that
# does not name the file, an input slower than 10 s or memory over 2 GB. The input that failed is
# kept under BUILD_DIR/artifacts/ and printed (escaped).
#
# Usage: tests/fuzz_parser.sh SRC_DIR [BUILD_DIR]     (BUILD_DIR default: SRC_DIR/build-fuzz)
# Environment: FUZZ_SECONDS (default 60), FUZZ_BUILD_JOBS (default 2).
set -euo pipefail
src=$(cd "${1:?usage: fuzz_parser.sh SRC_DIR [BUILD_DIR]}" && pwd)
build=${2:-$src/build-fuzz}
seconds=${FUZZ_SECONDS:-60}
jobs=${FUZZ_BUILD_JOBS:-2}

cxx=$(command -v clang++ || true)
if [ -z "$cxx" ] || ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a > /dev/null 2>&1; then
  echo "fuzz_parser: clang++ or libFuzzer missing (apt-get install -y clang libclang-rt-14-dev)" >&2
  exit 1
fi

start=$(date +%s)
mkdir -p "$build"
cmake -S "$src" -B "$build" -DMULTIFLUID_FUZZ=ON -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  > "$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; exit 1; }
cmake --build "$build" --target scene_fuzzer -j"$jobs" > "$build/build.log" 2>&1 || { tail -50 "$build/build.log" >&2; exit 1; }
built=$(date +%s)
echo "fuzz_parser: scene_fuzzer built in $((built - start)) s"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/corpus" "$build/artifacts"
cp "$src"/tests/fuzz/corpus/* "$work/corpus/"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$src/tests/fuzz/ubsan.supp"
set +e
"$build/tests/fuzz/scene_fuzzer" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 -print_final_stats=1 \
  -dict="$src/tests/fuzz/scene.dict" -artifact_prefix="$build/artifacts/" "$work/corpus" > "$work/fuzz.log" 2>&1
status=$?
set -e
end=$(date +%s)
inputs=$(ls "$work/corpus" | wc -l)
if [ "$status" -ne 0 ]; then
  echo "fuzz_parser: FAILED (exit $status) after $((end - built)) s of fuzzing; the fuzzer's report:" >&2
  grep -v -E '^#[0-9]+[[:space:]]+(NEW|REDUCE|pulse|INITED|RELOAD)|NEW_FUNC' "$work/fuzz.log" | tail -80 >&2
  for a in $(grep -o "Test unit written to [^ ]*" "$work/fuzz.log" | sed 's/Test unit written to //'); do
    echo "--- input $a ($(wc -c < "$a") bytes), escaped:" >&2
    head -c 2000 "$a" | od -c | head -40 >&2
  done
  exit 1
fi
grep -E '^(stat::|Done)' "$work/fuzz.log" || true
echo "fuzz_parser: no crash in $((end - built)) s of fuzzing ($inputs corpus inputs at the end); $((end - start)) s in all"
