// Internal: per-face failures (ENGINEERING.md, habit 4). A picked face whose
// geometry defeats a phase of a finishing job (a degenerate face, an
// OpenCASCADE failure on it, a recursion guard tripped) is reported by name
// and skipped; the rest of the job goes on. Only when every picked face
// fails is the job an error.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace isocam {

// Runs fn, work on the face `face` (its index in the shape). Returns nothing
// if it succeeded; else why it failed, naming the face (face_label(face)
// first): a GeometryError's message, or an OpenCASCADE Standard_Failure's as
// "OpenCASCADE failed: ...". InvalidArgument, Cancelled and any other
// exception pass through: a bad argument or a cancel ends the job.
std::optional<std::string> face_failure(int face, const std::function<void()>& fn);

// The warning for a picked face skipped for `reason` (face_failure()'s): no
// path on it. `in_model`: the clearance model still keeps the ball (or the
// tool) clear of it; otherwise the warning says that it is not protected.
std::string skipped_face_warning(const std::string& reason, bool in_model);

// The error when every picked face failed: a GeometryError naming each face
// with its reason.
[[noreturn]] void throw_every_face_failed(const std::vector<std::string>& reasons);

}  // namespace isocam
