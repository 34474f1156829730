# Sourced by the window tests (journeys/lib.sh, xvfb_start.sh): the one way they wait.
#
# wait_until CONDITION SECS [WHAT]: evaluates the shell text CONDITION (in the caller's
# variables) every 50 ms until it holds, and returns as soon as it does; after SECS × 20
# tries (SECS seconds at least, more on a loaded machine where a try itself takes time)
# calls `fail` (the sourcing script's) saying what it waited for (WHAT, else
# CONDITION). A test waits for the event itself (a file, a log line, a state the last
# frame showed, the process gone), never for a fixed time.
wait_until() {
    local _wu_cond=$1 _wu_what=${3:-$1} _wu_tries
    _wu_tries=$(awk -v s="$2" 'BEGIN { n = int(s * 20); print (n < 1 ? 1 : n) }')
    until eval "$_wu_cond"; do
        ((--_wu_tries > 0)) || fail "after $2 s, waited in vain for: $_wu_what"
        sleep 0.05
    done
}
