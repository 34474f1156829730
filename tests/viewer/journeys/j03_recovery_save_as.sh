#!/bin/bash
# Journey: a false "the viewer did not close normally" banner. The user types into the
# text of a.txt, waits long enough for the crash-recovery copy to be written, saves it
# as b.txt and quits normally; then opens a.txt and b.txt again.
# Checks: after the normal quit no recovery copy is left; neither file offers
# recovered text on the next start.
# Usage: j03_recovery_save_as.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

RECOVERY=$XDG_STATE_HOME/raytracer-view/recovery
copies() { find "$RECOVERY" -type f ! -name '*.lock' 2>/dev/null | wc -l; }

step "type into a.txt and wait for the recovery copy"
cp "$SCENES/default.txt" "$OUT/a.txt"
start_viewer "$OUT/a.txt"
key ctrl+e
wait_state editor_grid "nowrap"
key ctrl+Home
type_text "// a note"
key Return
wait_until '[ "$(copies)" -ge 1 ]' 10 "a recovery copy of the unsaved text"

step "save as b.txt and quit normally"
key Escape ctrl+shift+s
wait_state popups "Save scene as"
wait_state browser_field "^active$"
key ctrl+a
type_text "$OUT/b.txt"
key Return
wait_state title '^b.txt - raytracer-view$'
head -1 "$OUT/b.txt" | grep -q '^// a note$' || fail "b.txt does not hold the typed text"
quit_viewer
[ "$(copies)" = 0 ] || fail "a normal quit left $(copies) recovery copies: $(ls "$RECOVERY")"

for f in a.txt b.txt; do
    step "open $f again: no recovered text on offer"
    start_viewer "$OUT/$f"
    idle 1
    wait_state banner "^none$" 1
    quit_viewer
done
echo PASS
