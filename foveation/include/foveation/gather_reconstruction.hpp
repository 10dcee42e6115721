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
  GatherStats reconstruct(const FrameContext& frame, const TracedPoints& traced, ImageRgb& out,
                          Executor& executor) override {
    return gather(tables_.neighbors, tables_.interpolation, traced.colors, frame.mapping, out, executor, options_);
  }

 private:
  const ViewTables& tables_;
  GatherOptions options_;
};

}  // namespace foveart::foveation
