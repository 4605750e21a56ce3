// The 3D view's HTML (scene3d.hpp): the controls and the data of one view, and the scripts every
// page with a view needs once (three.js, its OrbitControls and the view's own script).
#pragma once

#include <string>

#include "redpost/report/scene3d.hpp"

namespace redpost::report {

// <div class="scene3d" id="ID"> with its controls, a note on what was decimated, and the data as
// a JSON <script> (binary arrays as little-endian base64).
std::string render_scene3d(const Scene3d& scene, const std::string& id);

// The scripts, to go after the last view: an error collector (for the browser test), three.js,
// OrbitControls and scene3d.js, each library marked data-library="...".
std::string scene3d_scripts();

}  // namespace redpost::report
