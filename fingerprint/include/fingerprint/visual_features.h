// Visual features of a panoramic image for a fingerprint of place (Tapus & Siegwart, "A Cognitive
// Modeling of Space using Fingerprints of Places", section 3: vertical edges and colour patches of
// an omnidirectional image, each with its bearing):
//  - a VERTICAL EDGE is a boundary between two image columns where the colour steps, in most rows
//    of the wall band, by more than the camera's noise could (edge_step_sigmas standard deviations
//    of the difference of two noisy pixels). In an equirectangular panorama from a level camera a
//    vertical line of the world - a door's jamb, a room's corner, a wall's end - is a column, so
//    one boundary holds all of it. Of neighbouring boundaries the strongest is kept.
//  - a COLOUR PATCH is a stretch of columns whose wall band has one hue (hue_bins bins around the
//    colour circle), saturated enough for its hue to be a colour rather than noise on a grey, and
//    at least min_patch_angle wide.
// The wall band is the rows within band_half_angle of the horizon: a camera 0.8 m above the floor
// sees a 2 m high wall fill it up to 0.8 / tan(band_half_angle) away (5.7 m for the default 0.14 rad),
// the size of a room, so the band shows walls and not the floor or ceiling.
//
// ROS-free: OpenCV and the standard library.
#pragma once

#include <opencv2/core.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace fingerprint {

/// How an equirectangular panorama's pixels map to directions, from camera_info's K: the left edge
/// of pixel column x (a real number) looks at bearing (cx - x) / fx (counter-clockwise from ahead),
/// row r's centre at elevation (cy - (r + 0.5)) / fy.
struct PanoramaModel {
  int width = 720;
  int height = 120;
  double fx = 720.0 / (2.0 * 3.14159265358979323846);  // px per rad around
  double fy = 120.0 / 1.0471975511965976;              // px per rad up and down
  double cx = 360.0, cy = 60.0;                         // px, the horizon ahead
  /// rad in (-pi, pi]: the bearing at pixel coordinate x.
  double bearingAt(double x) const;
  double elevation(int row) const { return (cy - (row + 0.5)) / fy; }
  /// A panorama: the columns cover the circle (width / fx = 2 pi within half a column), fy > 0.
  bool valid(std::string* why = nullptr) const;
};

enum class FeatureType : uint8_t { VerticalEdge = 1, ColorPatch = 2, LaserCorner = 3, LaserDoor = 4, LaserJunction = 5 };

/// One feature of a fingerprint (hybrid_slam_msgs/FingerprintFeature).
struct Feature {
  FeatureType type = FeatureType::VerticalEdge;
  double bearing = 0.0;  // rad, camera frame, in (-pi, pi]; a patch's centre
  double sigma = 0.0;    // rad, of the bearing
  double width = 0.0;    // rad, a patch's extent
  int hue_bin = -1;      // a patch's; -1 for the others
  std::array<uint8_t, 3> color{{0, 0, 0}};  // a patch's mean colour (rgb)
  double strength = 0.0;  // [0, 1]
};

/// Parameters of VisualFeatureExtractor (config/fingerprint.yaml; each with its unit and default).
struct VisualFeatureParams {
  double image_noise_stddev = 2.0;  // levels (0-255) per channel: the camera's (camera/noise_stddev, shared)
  double band_half_angle = 0.14;    // rad, the wall band's rows lie within this of the horizon
  double edge_step_sigmas = 6.0;    // -, an edge's step, in standard deviations of a difference of two pixels
  double edge_min_share = 0.7;      // -, of the band's rows an edge's step covers
  int hue_bins = 12;                // bins of the colour circle (30 deg each)
  double min_saturation = 0.15;     // -, HSV saturation of a patch (below: grey, white, black)
  double min_patch_angle = 0.05;    // rad, a patch's least extent (a door frame at 2 m)
};

class VisualFeatureExtractor {
 public:
  /// Throws std::invalid_argument when validate() refuses `params`.
  explicit VisualFeatureExtractor(const VisualFeatureParams& params = VisualFeatureParams());
  static bool validate(const VisualFeatureParams& params, std::string* error = nullptr);
  const VisualFeatureParams& params() const { return params_; }

  /// The edges and patches of `rgb` (CV_8UC3, rgb order, model.height x model.width), appended to
  /// `out` in order of column. False (nothing appended) when the image does not match the model or
  /// the model is no panorama; `error` says why.
  bool extract(const cv::Mat& rgb, const PanoramaModel& model, std::vector<Feature>* out, std::string* error = nullptr);

 private:
  void findEdges(const cv::Mat& rgb, const PanoramaModel& model, std::vector<Feature>* out);
  void findPatches(const cv::Mat& rgb, const PanoramaModel& model, std::vector<Feature>* out);

  VisualFeatureParams params_;
  int band_begin_ = 0, band_end_ = 0;  // rows [begin, end) of the band, for the last model
  std::vector<float> share_;           // per column boundary (scratch)
  cv::Mat column_mean_, column_hsv_;   // 1 x width, CV_32FC3 (scratch)
};

}  // namespace fingerprint
