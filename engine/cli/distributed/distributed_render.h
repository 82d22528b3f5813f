#pragma once
// `dynrt render` across the processes of an MPI job, or resumable in one (distributed_render.cpp).

#include "distributed/cluster.h"
#include "frame_args.h"

namespace dynrt::cli {

/// Renders args' frames across `cluster`'s ranks (every rank calls it) as args.distribute
/// says ("frames" or "tiles"), skipping with args.resume the frames an earlier run finished.
/// Returns the exit code; a failure stops every rank (Cluster::fail), or alone throws.
int run_distributed_render(const RenderArgs& args, Cluster& cluster);

}  // namespace dynrt::cli
