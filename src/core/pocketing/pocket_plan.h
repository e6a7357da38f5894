// The pocketing pipeline's internal stages (not public API):
//   offset tree (offset_tree.cpp) -> cutting order and links
//   (spiral_link.cpp) -> moves (pocket_emit.cpp, floor_path.cpp).
#pragma once

#include <functional>
#include <vector>

#include "isocam/pocketing.h"
#include "isocam/profile2d.h"
#include "isocam/progress.h"
#include "pocketing/geom2d.h"

namespace isocam::pocket {

// A node of Suh & Lee's offset tree (section 2.3, Figure 2.20): one
// connected piece of the region at one offset step: its outer profile (a
// shrunk boundary or a lake) first, then its grown islands. Its children
// are the pieces of it shrunk by `step`.
struct P3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

struct TreeNode {
  std::vector<Loop> loops;
  int parent = -1;
  std::vector<int> children;
  int depth = 0;
  double step = 0.0;  // the interval to the children
  // Sculptured floor: per loop, per segment, the CL points after the
  // segment's start (tool tip), filled by the step function.
  std::vector<std::vector<std::vector<P3>>> cl;
};

struct OffsetTree {
  std::vector<TreeNode> nodes;
  std::vector<int> roots;  // the region shrunk by r (allowed tool centres)
  int reduced = 0;         // steps reduced to leave no material
  double min_step = 0.0, max_step = 0.0;
};

// The interval from a node to its children (> 0) and the reach: the plan
// distance from a loop within which a point counts as machined. For a flat
// floor the stepover and the tool radius r; for a sculptured floor the
// interval W of eq. 11-18 (the smallest along the node's loops) and W / 2,
// the distance at which the scallop reaches its height.
struct Step {
  double step = 0.0;
  double reach = 0.0;
};
using StepFunction = std::function<Step(TreeNode&)>;

struct TreeOptions {
  double radius = 0.0;   // tool radius r
  double cov_tol = 0.0;  // coverage slack: material thinner than 2 cov_tol is ignored
  double snap = 0.0;
  double max_segments = 1e300;  // the tree's loops may hold at most this many segments
};

// Builds the tree: roots = the region shrunk by r, then each node shrunk by
// its step until nothing is left. Where a step larger than the reach would
// leave points farther than the reach from both a node's loops and its
// children's loops (sharp corners, narrow fingers, the middle of a piece
// that vanishes), it is reduced (never below the reach, for which nothing
// can be left: every point of the band is within the reach of the node's
// loops).
OffsetTree build_offset_tree(const std::vector<Loop>& region, const TreeOptions& opt,
                             const StepFunction& step, const ProgressSlice& progress);

// One loop to cut: its node and index there, the start point (segment and
// parameter) and how the tool gets there.
enum class LinkKind { Start, Feed, Retract };
struct LoopCut {
  int node = 0, loop = 0, seg = 0;
  double t = 0.0;
  LinkKind link = LinkKind::Start;
};

struct OrderOptions {
  double radius = 0.0;
  double snap = 0.0;
  // Start points may only be the end points of segments (the sculptured
  // floor's loops are cut from a vertex of their CL polyline).
  bool vertices_only = false;
  ProgressSlice progress;  // polled for a cancel at every node
};

// Cutting order (section 2.3): deepest profile first, climbing to the
// parent, the brothers (nearest first) before their parent; the loops of a
// node nearest first. Each loop starts at its point nearest to where the
// tool is; the link is a feed move when it stays inside the allowed region
// (no gouge) and inside the already cut area except for its last `step`
// (the band it steps over, as a spiral does), otherwise a retract.
std::vector<LoopCut> order_cuts(const OffsetTree& tree, const OrderOptions& opt);

// A loop as cut from a start point, in the direction of travel (climb: as
// stored, region on the left; conventional: reversed).
Loop loop_from(const Loop& loop, int seg, double t, bool climb, double snap);

}  // namespace isocam::pocket
