#!/bin/bash
# Journey: the panel of a CSG operand. The user selects "left: sphere" under the CSG in
# the outline and looks at its fields, then selects the whole CSG.
# Checks: the operand's panel offers its shape's keys and no material (only the whole
# CSG's material is rendered: sliders there would change the text and nothing in the
# picture) and says where the material is; the CSG's panel offers the material.
# Usage: j15_operand_material.sh BIN_DIR OUT_DIR
. "$(dirname "$0")/lib.sh" "$@"

step "open default.txt, select the CSG's left operand"
start_viewer "$SCENES/default.txt" --samples 4
click_item "outline_object_4_left"
wait_state selection "^object_4_left$"
idle 0.3
shot 1-operand
fields=$(state fields)
echo "the operand's fields: $fields"
[[ ",$fields," == *",position,"* && ",$fields," == *",radius,"* ]] || fail "the sphere's keys are not offered: $fields"
[[ ",$fields," != *",material"* ]] || fail "the operand's panel offers a material that is not rendered: $fields"

step "select the whole CSG: its material is offered"
click_item "button_select_the_parent"
wait_state selection "^object_4$"
idle 0.3
shot 2-csg
fields=$(state fields)
echo "the CSG's fields: $fields"
[[ ",$fields," == *",material,"* ]] || fail "the CSG's panel does not offer its material: $fields"
echo PASS
