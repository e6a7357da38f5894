// The guard in front of OpenCASCADE's B-rep reader (brep_guard.cpp).
#pragma once

#include <string>

namespace isocam::detail {

// Throws InvalidArgument("brep: ... at byte N") when the text announces
// more than it holds, ends inside an entry, or carries numbers no geometry
// has (NaN, inf, |x| > 1e100, weights <= 0 or spanning more than 1e12).
void check_brep_text(const std::string& text);

}  // namespace isocam::detail
