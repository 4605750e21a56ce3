// Text files inlined into the reports at build time (cmake/embed_text.cmake): three.js and its
// OrbitControls from Debian's libjs-three (never vendored: read from the installed package), and
// the 3D view's own script.
#pragma once

namespace redpost::report::assets {

extern const char* const three_js;
extern const char* const three_orbit_controls_js;
extern const char* const scene3d_js;
// "111+dfsg1-3": the libjs-three package the build read (dpkg), or "unknown".
extern const char* const three_package_version;

}  // namespace redpost::report::assets
