// What the status bar adds to a message about the document.
#pragma once

#include <string>

#include "document.h"
#include "status.h"

namespace rtview {

// About a scene without lights: everything in it is black.
inline std::string light_note(const Document& doc) {
    if (!doc.has_scene() || !doc.scene().lights.empty()) return {};
    return "; the scene has no lights, so it renders black: add a lamp (right-click the picture > Add here > lamp)";
}

// When the recent-files list could not be saved.
inline std::string recent_note(const rt::Status& recent) {
    return recent ? std::string() : "; recent files not saved: " + recent.message();
}

}  // namespace rtview
