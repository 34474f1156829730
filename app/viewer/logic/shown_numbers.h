// Numbers as the panels show them. A value a widget computes (a light's colour from a
// tint and an intensity, a colour picker's float channels) goes into the scene as the
// decimal its field shows, so that the text holds what a person would have typed
// (36.667, not 36.666666666666664) and the panel, the text and the picture agree.
#pragma once

namespace rtview {

// `v` as a field with `decimals` digits after the point shows it ("%.3f"), read back:
// the double nearest that decimal. Values too large to print are returned as they are.
double as_shown(double v, int decimals);

// A channel a float widget edited, shown with `decimals` digits: the scene's own value
// `was` when the widget did not change it (a float cannot hold 0.8 exactly: writing it
// back would put 0.800000011920929 into the text), else the value as shown.
double from_widget(double was, float now, int decimals);

// `v` to twelve significant digits, read back: a sum like 2.07 - 2.5 gives
// -0.43000000000000016, and a moved or turned item's numbers should read as a person
// would write them (-0.43). Infinities and NaN are returned as they are.
double twelve_digits(double v);

}  // namespace rtview
