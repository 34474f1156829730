// Number fields of the panels: a drag (or slider) changes the value live, as it moves;
// typed text (Ctrl+click or double-click, then Enter or leaving the field) changes it
// once, whole or not at all: "1e1" on the way to "1e16" is never applied, and text
// that is no number is refused with the parser's message instead of being dropped.
#pragma once

#include <string>

namespace rtview {

struct NumberFieldSpec {
    float speed = 1;                // drag speed per pixel
    const double* min = nullptr;    // drag or slider limits (the slider needs both)
    const double* max = nullptr;
    const char* format = "%.3f";
    bool slider = false;            // a slider between min and max, else a drag
    bool clamp_typed = false;       // typed values are clamped into [min, max] (with a note)
    const double* least = nullptr;  // typed values below it become it (with a note)
};

// One number, labelled; true when *v changed this frame.
bool number_field(const char* label, double* v, const NumberFieldSpec& spec);
// `n` numbers in one row (a point, two angles) with one label after them.
bool number_fields(const char* label, double* v, int n, const NumberFieldSpec& spec);
// Whether a field is being typed into (its value is not yet applied).
bool number_typing();
// The message for typed text that was refused since the last call, if any (`error`
// false: a note, as for a value brought into the field's range); `label`: the label of
// the field it was typed into.
bool take_number_refusal(std::string& message, bool* error = nullptr, std::string* label = nullptr);

}  // namespace rtview
