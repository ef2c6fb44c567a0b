#include "fingerprint/visual_features.h"

#include <opencv2/imgproc.hpp>

#include "laser_features/geometry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fingerprint {
namespace {

using laser_features::kPi;
using laser_features::normalizeAngle;

}  // namespace

double PanoramaModel::bearingAt(double x) const { return normalizeAngle((cx - x) / fx); }

bool PanoramaModel::valid(std::string* why) const {
  auto fail = [&](const std::string& text) {
    if (why) *why = text;
    return false;
  };
  if (width < 4 || height < 1) return fail("the image is smaller than 4 x 1 pixels");
  if (!(fx > 0.0 && fy > 0.0)) return fail("camera_info's K has no positive fx and fy");
  if (std::abs(width / fx - 2.0 * kPi) > 0.5 / fx)
    return fail("not a panorama: " + std::to_string(width) + " columns at fx " + std::to_string(fx) +
                " px/rad cover " + std::to_string(width / fx) + " rad, not 2 pi");
  return true;
}

bool VisualFeatureExtractor::validate(const VisualFeatureParams& p, std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (!(p.image_noise_stddev >= 0.0)) return fail("image_noise_stddev must be >= 0");
  if (!(p.band_half_angle > 0.0 && p.band_half_angle < 1.5)) return fail("band_half_angle must be in (0, 1.5) rad");
  if (!(p.edge_step_sigmas > 0.0)) return fail("edge_step_sigmas must be > 0");
  if (!(p.edge_min_share > 0.0 && p.edge_min_share <= 1.0)) return fail("edge_min_share must be in (0, 1]");
  if (p.hue_bins < 2 || p.hue_bins > 254) return fail("hue_bins must be in 2 .. 254");
  if (!(p.min_saturation >= 0.0 && p.min_saturation < 1.0)) return fail("min_saturation must be in [0, 1)");
  if (!(p.min_patch_angle > 0.0)) return fail("min_patch_angle must be > 0");
  return true;
}

VisualFeatureExtractor::VisualFeatureExtractor(const VisualFeatureParams& params) : params_(params) {
  std::string why;
  if (!validate(params, &why)) throw std::invalid_argument("visual features: " + why);
}

bool VisualFeatureExtractor::extract(const cv::Mat& rgb, const PanoramaModel& model, std::vector<Feature>* out,
                                     std::string* error) {
  if (!model.valid(error)) return false;
  if (rgb.type() != CV_8UC3 || rgb.rows != model.height || rgb.cols != model.width) {
    if (error)
      *error = "the image is " + std::to_string(rgb.cols) + " x " + std::to_string(rgb.rows) +
               " (8-bit, 3 channels: " + (rgb.type() == CV_8UC3 ? "yes" : "no") + "), camera_info says " +
               std::to_string(model.width) + " x " + std::to_string(model.height);
    return false;
  }
  band_begin_ = model.height;
  band_end_ = 0;
  for (int r = 0; r < model.height; ++r) {
    if (std::abs(model.elevation(r)) > params_.band_half_angle) continue;
    band_begin_ = std::min(band_begin_, r);
    band_end_ = std::max(band_end_, r + 1);
  }
  if (band_begin_ >= band_end_) {
    if (error) *error = "no image row lies within band_half_angle of the horizon";
    return false;
  }
  findEdges(rgb, model, out);
  findPatches(rgb, model, out);
  return true;
}

void VisualFeatureExtractor::findEdges(const cv::Mat& rgb, const PanoramaModel& model, std::vector<Feature>* out) {
  const int W = model.width;
  // The difference of two pixels with independent noise has sqrt(2) times a pixel's deviation.
  const double step = params_.edge_step_sigmas * std::sqrt(2.0) * params_.image_noise_stddev;
  const int threshold = int(std::floor(step));  // a step counts when it exceeds this many levels
  const int rows = band_end_ - band_begin_;
  share_.assign(W, 0.0f);  // share_[c]: the boundary between column c and c + 1 (circular)
  for (int r = band_begin_; r < band_end_; ++r) {
    const uint8_t* row = rgb.ptr<uint8_t>(r);
    for (int c = 0; c < W; ++c) {
      const uint8_t* a = row + 3 * c;
      const uint8_t* b = row + 3 * ((c + 1) % W);
      const int d = std::max({std::abs(a[0] - b[0]), std::abs(a[1] - b[1]), std::abs(a[2] - b[2])});
      if (d > threshold) share_[c] += 1.0f;
    }
  }
  for (float& s : share_) s /= float(rows);
  // Columns are 1 / fx wide: an edge lies anywhere across its boundary's pixel, uniformly.
  const double sigma = 1.0 / (model.fx * std::sqrt(12.0));
  for (int c = 0; c < W; ++c) {
    const float s = share_[c];
    if (s < params_.edge_min_share) continue;
    const float left = share_[(c + W - 1) % W], right = share_[(c + 1) % W];
    if (s < left || s <= right) continue;  // the strongest of neighbouring boundaries (ties: the first)
    Feature f;
    f.type = FeatureType::VerticalEdge;
    f.bearing = model.bearingAt(c + 1.0);
    f.sigma = sigma;
    f.strength = s;
    out->push_back(f);
  }
}

void VisualFeatureExtractor::findPatches(const cv::Mat& rgb, const PanoramaModel& model, std::vector<Feature>* out) {
  const int W = model.width;
  cv::Mat band;
  rgb.rowRange(band_begin_, band_end_).convertTo(band, CV_32FC3, 1.0 / 255.0);
  cv::reduce(band, column_mean_, 0, cv::REDUCE_AVG, CV_32FC3);  // 1 x W, rgb in [0, 1]
  cv::cvtColor(column_mean_, column_hsv_, cv::COLOR_RGB2HSV);    // H in [0, 360), S, V in [0, 1]
  std::vector<int> bin(W);
  for (int c = 0; c < W; ++c) {
    const cv::Vec3f hsv = column_hsv_.at<cv::Vec3f>(0, c);
    bin[c] = hsv[1] < params_.min_saturation ? -1
                                              : std::min(params_.hue_bins - 1, int(hsv[0] / 360.0f * params_.hue_bins));
  }
  // Runs of one bin around the circle, starting where the bin changes (none: the whole circle is one).
  int start = 0;
  while (start < W && bin[start] == bin[(start + W - 1) % W]) ++start;
  if (start == W) start = 0;
  for (int k = 0; k < W;) {
    const int c0 = (start + k) % W;
    int n = 1;
    while (k + n < W && bin[(start + k + n) % W] == bin[c0]) ++n;
    const double width = n / model.fx;
    if (bin[c0] >= 0 && width >= params_.min_patch_angle) {
      cv::Vec3f sum(0, 0, 0);
      float saturation = 0.0f;
      for (int j = 0; j < n; ++j) {
        sum += column_mean_.at<cv::Vec3f>(0, (c0 + j) % W);
        saturation += column_hsv_.at<cv::Vec3f>(0, (c0 + j) % W)[1];
      }
      Feature f;
      f.type = FeatureType::ColorPatch;
      f.bearing = model.bearingAt(c0 + 0.5 * n);
      f.width = width;
      f.sigma = width / std::sqrt(12.0);  // its centre, partly hidden: anywhere over its extent
      f.hue_bin = bin[c0];
      for (int ch = 0; ch < 3; ++ch) f.color[ch] = uint8_t(std::lround(255.0f * sum[ch] / n));
      f.strength = saturation / n;
      out->push_back(f);
    }
    k += n;
  }
}

}  // namespace fingerprint
