# Sourced by tools/deps.sh, build.sh and venv.sh: run one set-up stage as one
# line on the terminal ("libkin: what (about N) ... done in M s"), with the
# stage's own output in a log file that is shown only if the stage fails.
#   stage "what it does" "about 40 s" build/logs/name.log command args...
KIN_LOG_DIR="${KIN_LOG_DIR:-build/logs}"

stage() {
    local what="$1" estimate="$2" log="$3"
    shift 3
    mkdir -p "$(dirname "$log")"
    printf 'libkin: %s (%s) ... ' "$what" "$estimate"
    local t0=$SECONDS rc=0
    "$@" >"$log" 2>&1 || rc=$?
    if [ "$rc" -ne 0 ]; then
        printf 'FAILED after %d s (exit %d); last lines of %s:\n' "$((SECONDS - t0))" "$rc" "$log"
        tail -n 30 "$log" | sed 's/^/  | /'
        exit "$rc"
    fi
    printf 'done in %d s\n' "$((SECONDS - t0))"
}
