// doctest's main for the viewer's window-independent tests (rtview_logic).
#define DOCTEST_CONFIG_IMPLEMENT_WITH_MAIN
#include <doctest/doctest.h>
