// Stage 4 of the frame on the CPU (thesis 4.3): every pixel a k-tap gather
// over the view's precomputed canvas tables (gather.hpp), NN, MSM and RBF alike.
#pragma once

#include "foveation/frame_stages.hpp"
#include "foveation/view_tables.hpp"

namespace foveart::foveation {

class GatherReconstruction final : public ReconstructStage {
 public:
  // `tables` must outlive this.
  GatherReconstruction(const ViewTables& tables, RbfClamp rbf_clamp) : tables_(tables) {
    options_.rbf_clamp = rbf_clamp;
  }
  // Into HostFrame::reconstructed.
  bool reconstruct(const FrameContext& frame, const TracedPoints& traced, FrameResources& resources,
                   Executor& executor, GatherStats* stats, std::string* error) override {
    HostFrame* host = host_frame(resources, "the CPU's gather", error);
    if (host == nullptr) return false;
    *stats = gather(tables_.neighbors, tables_.interpolation, traced.colors, frame.mapping, host->reconstructed,
                    executor, options_);
    return true;
  }

 private:
  const ViewTables& tables_;
  GatherOptions options_;
};

}  // namespace foveart::foveation
