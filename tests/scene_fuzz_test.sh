#!/usr/bin/env bash
# Malformed-scene corpus: generates some 450 broken scenes from the shipped ones
# (tests/fuzz/make_corpus.py: the classes measured to crash, hang or run empty today, bad names,
# syntax errors, truncations, wrong types, unknown and duplicate keys, huge, NaN and out-of-range
# numbers, random bytes, 50 MB files) and runs `BIN validate FILE` on each under ulimit -v 2000000
# and timeout 60 (tests/fuzz/run_corpus.py, two at a time). Each must exit non-zero, not by a
# signal or the timeout, with a message that names the file (and the line and key where the
# index expects them). Prints a line per class, every failure, and "N passed, N failed".
# Usage: tests/scene_fuzz_test.sh BIN SRC_DIR
set -euo pipefail
bin=$(realpath "${1:?usage: scene_fuzz_test.sh BIN SRC_DIR}")
src=${2:?usage: scene_fuzz_test.sh BIN SRC_DIR}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 "$src/tests/fuzz/make_corpus.py" "$work/corpus" --configs "$src/configs"
python3 "$src/tests/fuzz/run_corpus.py" "$bin" "$work/corpus" --jobs "${SCENE_FUZZ_JOBS:-2}"
