#!/bin/sh
# Run each fuzz target: over its stored corpus (tests/fuzz/corpus/TARGET)
# and the seeds of valid structures that fuzz_seeds writes (the built-in
# models, examples/models, real merge records: fuzz_seeds.c), then SECONDS
# seconds of new inputs (default 3: the short run of the test suite, ctest
# fuzz_short). New inputs go to a scratch copy of the corpus, so the
# repository is not changed. Exit 1 on the first crash (its input is left in
# the scratch folder, named crash-*).
# usage: run.sh BINDIR SRCDIR [SECONDS]
set -eu
bin=$(cd "$1" && pwd) src=$(cd "$2" && pwd) secs=${3:-3}
work=$(mktemp -d "${TMPDIR:-/tmp}/kin_fuzz.XXXXXX")
for t in fuzz_load fuzz_create fuzz_merge; do mkdir -p "$work/$t"; done
if [ -x "$bin/fuzz_seeds" ]; then
    "$bin/fuzz_seeds" "$work" "$src"/../../examples/models/*.json || { echo "fuzz: fuzz_seeds failed"; exit 1; }
fi
for t in fuzz_load fuzz_create fuzz_merge; do
    if [ -d "$src/corpus/$t" ]; then cp "$src/corpus/$t"/* "$work/$t"/ 2>/dev/null || true; fi
    dict=""
    if [ -f "$src/$t.dict" ]; then dict="-dict=$src/$t.dict"; fi
    echo "fuzz: $t, $secs s"
    (cd "$work" && ASAN_OPTIONS=detect_leaks=1 "$bin/$t" $dict -max_total_time="$secs" -max_len=4096 \
        -rss_limit_mb=1024 -timeout=10 -print_final_stats=0 "$work/$t" 2>"$work/$t.log") || {
        tail -40 "$work/$t.log"; echo "fuzz: $t failed; inputs and log in $work"; exit 1; }
done
rm -rf "$work"
echo "fuzz: all targets ok"
