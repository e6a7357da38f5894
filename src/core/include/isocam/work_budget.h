// Limits checked before the work (issue 15): a tolerance too fine for the
// model's size, or a job whose output would be too large, is refused in
// milliseconds with a message naming both values, instead of running for
// minutes or exhausting memory.
#pragma once

#include <string>

namespace isocam {

// The largest ratio of the model's extent (its bounding box, measured from
// the origin: max(size, distance of the box from the origin)) to a length
// tolerance (chord tolerance, scallop height, pocketing tolerance,
// stepover). Beyond it double precision leaves too few digits for the
// tolerances the core works with.
constexpr double kMaxExtentToTolerance = 1e6;

// The default largest number of moves an operation computes (IsoParams and
// PocketParams max_moves; the FreeCAD ops' MaxMoves): some 50 MB of path
// and, at the core's speed, up to about a minute of work.
constexpr double kDefaultMaxMoves = 1e6;

// Throws InvalidArgument unless 0 < tol and extent / tol <= kMaxExtentToTolerance.
void check_tolerance_ratio(const std::string& name, double tol, double extent);

// Throws InvalidArgument unless max_moves is finite and >= 1.
void check_max_moves(double max_moves);

// Throws InvalidArgument("work budget: about N moves (how) exceed max_moves = M ...")
// when estimate > max_moves.
void check_work_budget(double estimate, double max_moves, const std::string& how);

}  // namespace isocam
