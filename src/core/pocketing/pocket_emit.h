// Shared steps of the pocketing operations (pocket_emit.cpp): parameter
// checks, the flat-floor plan and its moves, metrics of a path.
#pragma once

#include <vector>

#include "isocam/pocketing.h"
#include "pocketing/pocket_plan.h"

namespace isocam::pocket {

// Throw InvalidArgument naming the parameter and its limit.
void check_params(const PocketParams& p, bool sculptured);
void check_depths(const std::vector<double>& depths, double safe_z);
// The tolerance and stepover against the region's extent, and the moves
// estimated for `levels` levels of it against max_moves (work_budget.h).
void check_plan_budget(const std::vector<Loop>& region, const PocketParams& p, std::size_t levels);
// Throws the work-budget error once the path holds more than max_moves moves.
void check_path_budget(const Toolpath& path, const PocketParams& p);

// Offset tree and cutting order of one region for a flat floor.
struct FlatPlan {
  OffsetTree tree;
  std::vector<LoopCut> cuts;
  double snap = 0.0;
};
FlatPlan make_flat_plan(const std::vector<Loop>& region, const PocketParams& p, double snap,
                        const ProgressSlice& progress);

// Moves from the end of `path` to s at height z: a feed link, or (Start /
// Retract) up to safe_z, across, and a plunge.
void move_to_start(Toolpath& path, P2 s, double z, LinkKind link, double safe_z);

// The cutting moves of one segment at height z: G1 for a line, G2/G3 of at
// most half a turn for an arc (G1 where the chord is shorter than min_chord).
void emit_seg_flat(Toolpath& path, const Seg& s, double z, double min_chord);

// All loops of a plan at height z (the first one entered from above).
void emit_flat_plan(const FlatPlan& plan, double z, const PocketParams& p, Toolpath& path,
                    PocketMetrics& m);

// Lengths, retracts, arcs and CL points of a path (the other metrics stay).
void measure_path(const Toolpath& path, PocketMetrics& m);

}  // namespace isocam::pocket
