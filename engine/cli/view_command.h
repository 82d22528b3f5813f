#pragma once
// `dynrt view` (view_command.cpp).

#include "../viewer/viewer_session.h"

namespace dynrt::cli {

/// Opens the viewer on `args`' scene; returns the exit status. Throws as run_render does for
/// a scene that cannot be read or bad flags, and std::runtime_error when no window can be
/// opened here (no display, or built without the viewer).
int run_view(const viewer::ViewArgs& args);

}  // namespace dynrt::cli
