// Every parameter of VisualFeatureExtractor with its name in config/fingerprint.yaml, in one list:
// the node reads them with it, the tests check the YAML's defaults against the code's with it.
// image_noise_stddev is the camera's (camera/noise_stddev, config/camera.yaml), not this node's.
#pragma once

#include "fingerprint/visual_features.h"

namespace fingerprint {

template <typename Visitor>
void visitParams(VisualFeatureParams* p, Visitor&& visit) {
  visit("band_half_angle", &p->band_half_angle);
  visit("edge_step_sigmas", &p->edge_step_sigmas);
  visit("edge_min_share", &p->edge_min_share);
  visit("hue_bins", &p->hue_bins);
  visit("min_saturation", &p->min_saturation);
  visit("min_patch_angle", &p->min_patch_angle);
}

}  // namespace fingerprint
