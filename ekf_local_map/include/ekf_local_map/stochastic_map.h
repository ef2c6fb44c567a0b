// One place's stochastic map (Smith, Self & Cheeseman 1990) on infinite lines, as Tomatis,
// Nourbakhsh & Siegwart 2001 (IROS, "Simultaneous localization and map building: a global
// topological model with local metric maps") use it inside rooms, section 3.4:
//
//   eq. 6       state x = (x_r, y_r, theta_r, alpha_1, r_1, ..., alpha_n, r_n) in the place frame
//               and its full covariance P
//   eqs. 7–8    prediction: x_r <- x_r (+) u,  P_rr <- F P_rr F^T + G U G^T,  P_rm <- F P_rm
//   eqs. 9–11   a new line: x_new = g(x_r, z),  P_new,new = J_r P_rr J_r^T + J_z R J_z^T,
//               P_new,. = J_r P_r,.
//   eq. 12      predicted measurement of a map line in the sensor frame, h(x)
//   eq. 13      innovation nu = z - h and the validation gate nu^T S^-1 nu < chi^2_2(level)
//   eq. 14      innovation covariance S = H P H^T + R
//   eqs. 15–17  gain K = P H^T S^-1, x <- x + K nu, P <- P - K S K^T
//
// Implementation notes (why it looks the way it does):
// - P is stored in a preallocated square buffer that grows geometrically; only its LOWER triangle
//   (diagonal included) is maintained, which halves the O(n^2) work of the update. Read it through
//   the accessors, which return symmetric matrices.
// - Prediction touches the robot rows only (O(n)).
// - All matches of a scan are fused in one stacked update: W = P H^T (H is sparse: robot and one
//   line per match), S = H W + R, S = L L^T (Cholesky), V = W L^-T, x += V L^-1 nu, P -= V V^T
//   (a symmetric rank-2k update of the lower triangle, N^2 k multiply-adds for N state entries and
//   k matches). This equals the Joseph form (I - K H) P (I - K H)^T + K R K^T for the optimal gain
//   (a test checks it against a dense Joseph reference) at a third of the cost of even a
//   sparsity-aware Joseph form, keeps P exactly symmetric, and the Cholesky factor of S keeps the
//   subtracted term positive semi-definite.
// - Association is global nearest neighbour: every (observation, line) pair with overlapping
//   segment extents inside the wide exclusion gate is a candidate; candidates are taken greedily
//   by increasing Mahalanobis distance, each observation and each line at most once per scan.
//   Pairs inside the validation gate (eq. 13, chi^2_2 at gate_probability) are accepted; pairs
//   outside it only when the whole set of pairs is jointly compatible (stacked NIS below
//   chi^2_2k at gate_probability), because a common robot-pose error moves all innovations out
//   of their individual gates at once.
// - After fusing, the observations still unmatched are associated once more against the
//   posterior (a second, sequential batch: exact, as the observations are independent), so that a
//   re-observation pushed out of its gate by a pose error the first batch corrected is fused rather
//   than turned into a duplicate line. Only then are new lines added (eqs. 9–11), from the
//   posterior robot pose.
// - A gating failure (lines expected, lines seen, none matched: an odometry jump or kidnapping)
//   leaves the state untouched and adds no line. "Expected" means within range and not hidden
//   behind an observed segment, so that entering an unmapped corner of a place is not a failure.
// - No heap allocation per scan in steady state (the buffers keep their capacity).
// Equation numbers are those of the paper's section 3.4 as issue 4 cites them (eqs. 6–17).
#pragma once

#include "ekf_local_map/measurement_model.h"
#include "ekf_local_map/update_kernels.h"

#include <laser_features/geometry.h>
#include <laser_features/line_extractor.h>

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace ekf_local_map {

/// Parameters of the stochastic map (unit, default, why).
struct StochasticMapParams {
  // Association (eq. 13)
  double gate_probability = 0.95;        // -, validation gate: chi^2_2 quantile, 0.95 -> 5.991
  double new_line_exclusion_nis = 40.0;  // -, chi^2_2 value: an unmatched observation within this
                                         //   Mahalanobis distance of a map line, extents overlapping, is
                                         //   ambiguous: neither fused nor added. A correct re-observation
                                         //   lies beyond it with probability exp(-20) = 2e-9 (a 0.9999
                                         //   gate would still make a duplicate line every 10^4 observations,
                                         //   i.e. every ~20 min at 10 lines x 10 Hz)
  double extent_margin = 1.0;            // m, an observed segment must overlap the map line's known extent
                                         //   or come this close to it, so that collinear walls of
                                         //   different rooms stay different lines
  // New lines (eqs. 9–11)
  uint32_t new_line_min_points = 10;     // -, scan points an observation needs to become a new line
  double new_line_min_length = 0.3;      // m, length an observation needs to become a new line
  // Observation noise
  double observation_cov_inflation = 1.0;  // -, multiplies the extractor's (alpha, r) covariance
  double observation_alpha_sigma_floor = 5e-4;  // rad, added in quadrature (walls are not perfectly straight)
  double observation_r_sigma_floor = 5e-4;      // m, likewise
  // Gating failure (odometry jump / teleport / kidnapping)
  double expected_line_range = 10.0;     // m, a map line whose known extent comes this close to the
                                         //   sensor is predicted to be seen, unless hidden: see below
  double occlusion_margin = 0.2;         // m, a map line is hidden when an observed segment crosses the
                                         //   ray to its closest known point this much nearer the sensor
  uint32_t gating_failure_min_expected = 3;      // -, predicted-visible lines needed to call a failure
  uint32_t gating_failure_min_observations = 2;  // -, valid observations needed to call a failure
  // Relocation (entering a known place)
  uint32_t relocation_min_matches = 3;   // -, matched lines needed to accept a relocation
  double relocation_joint_probability = 0.99;  // -, the stacked innovation of all matches must be
                                         //   jointly compatible: nu^T S^-1 nu < chi^2_2k(this)
  double relocation_min_angle = 0.35;    // rad (20 deg), the matched lines must span at least this
                                         //   angle, so that they fix the pose in both directions
  // Storage
  size_t initial_line_capacity = 32;     // -, lines preallocated (grown by doubling)
};

/// What became of one observation in an update.
enum class ObservationOutcome : uint8_t {
  kMatched,                         // associated with a map line (fused unless report.fused is false:
                                    //   a failed relocation)
  kNewLine,                         // added to the map (eqs. 9–11)
  kRejectedNotFinite,               // NaN / infinity anywhere: never fused
  kRejectedCovarianceNotPD,         // covariance not symmetric positive definite: never fused
  kOutOfGate,                       // in no map line's gate and too weak (points, length) for a new line,
                                    //   or new lines were suspended (gating failure, relocation)
  kAmbiguous,                       // in a line's wider exclusion gate but not accepted (outside
                                    //   the validation gate and not jointly compatible, or the line
                                    //   was taken by a closer observation): neither fused nor added
};
const char* toString(ObservationOutcome outcome);

/// One accepted (observation, map line) pair.
struct LineMatch {
  uint32_t observation = 0;  // index into the observations given to update()
  uint32_t line = 0;         // map line index
  double nis = 0.0;          // normalized innovation squared nu^T S^-1 nu (eq. 13), against the
                             //   prior (or, for the second pass, the first batch's posterior)
};

/// Result of a relocation attempt (see StochasticMap::relocate).
struct RelocationResult {
  enum class Verdict : uint8_t {
    kSuccess,
    kTooFewMatches,         // fewer than relocation_min_matches lines matched
    kJointlyIncompatible,   // the matches are individually plausible but not together (wrong room)
    kParallelLines,         // the matched lines are (nearly) all parallel: pose not fixed
  };
  Verdict verdict = Verdict::kTooFewMatches;
  uint32_t matched = 0;
  double joint_nis = 0.0;       // nu^T S^-1 nu of the stacked matches
  double joint_nis_bound = 0.0; // chi^2_2k(relocation_joint_probability)
  double angle_span = 0.0;      // rad, largest angle between two matched map lines
  bool success() const { return verdict == Verdict::kSuccess; }
};
const char* toString(RelocationResult::Verdict verdict);

/// What an update did. Reuse one report across scans: its vectors keep their capacity.
struct UpdateReport {
  uint32_t observations = 0;
  uint32_t matched = 0;
  uint32_t new_lines = 0;
  uint32_t rejected_not_finite = 0;
  uint32_t rejected_not_positive_definite = 0;
  uint32_t out_of_gate = 0;
  uint32_t ambiguous = 0;
  uint32_t expected_lines = 0;    // map lines predicted to be within sight (computed when nothing matched)
  double mean_nis = 0.0;          // mean NIS of the matches (chi^2_2: 2 when consistent); 0 without matches
  double joint_nis = 0.0;         // NIS of all matches stacked (chi^2 with 2 * matched dof)
  bool gating_failure = false;    // lines expected and seen, none matched: the state was not updated
  bool fused = false;             // the state was updated with the matches
  bool relocation_attempted = false;  // this update evaluated a pending relocation
  RelocationResult relocation;        // valid when relocation_attempted
  std::vector<ObservationOutcome> outcomes;  // per observation
  std::vector<LineMatch> matches;

  void clear();
};

/// A map line: (alpha, r) in the place frame with its 2x2 marginal covariance, and the part of
/// it seen so far (two points on the line; the extent grows on every match).
struct MapLine {
  Line line;
  Eigen::Vector2d extent_start = Eigen::Vector2d::Zero();
  Eigen::Vector2d extent_end = Eigen::Vector2d::Zero();
  double length() const { return (extent_end - extent_start).norm(); }
};

class StochasticMap {
 public:
  using Params = StochasticMapParams;

  /// An empty place: the robot at the origin with zero covariance (the place frame is the robot's
  /// pose on entry).
  explicit StochasticMap(const Params& params = Params());

  const Params& params() const { return params_; }
  void setParams(const Params& params) { params_ = params; }

  // ---- eqs. 7–8 ----------------------------------------------------------------------------
  /// Moves the robot by an odometry increment (in the robot frame at the start of the increment)
  /// with its covariance (see OdometryNoise). O(n). Returns false, changing nothing, when the
  /// increment or its covariance is not finite.
  bool predict(const Pose2D& odom_increment, const Eigen::Matrix3d& increment_cov);

  // ---- eqs. 9–17 ---------------------------------------------------------------------------
  /// Associates the observed segments (line covariance in the SENSOR frame) with the map lines,
  /// fuses the matches and adds the well-supported unmatched ones as new lines. `sensor_in_robot`
  /// is the laser's pose on the robot. `report` may be null.
  /// With no match (a gating failure, e.g. after a teleport) the state is left as it was and no
  /// line is added. While a relocation is pending (see relocate) the matches are fused only if they
  /// pass the relocation test, and no line is added.
  void update(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot,
              UpdateReport* report);

  // ---- relocation (entering a known place through a door) ---------------------------------
  /// Resets the robot part of the state: pose and covariance set, robot–map cross-covariances
  /// zeroed (the robot's past in this place is forgotten). The next update() evaluates the
  /// relocation (report->relocation): success needs relocation_min_matches matched lines that are
  /// jointly compatible and span relocation_min_angle. On failure nothing is fused or added and the
  /// relocation stays pending, so that the caller can back out or try again. Returns false,
  /// changing nothing, for a non-finite pose or covariance.
  bool relocate(const Pose2D& pose_in_place, const Eigen::Matrix3d& cov);
  bool relocationPending() const { return relocation_pending_; }

  // ---- state ------------------------------------------------------------------------------
  size_t numLines() const { return extents_.size(); }
  size_t stateSize() const { return 3 + 2 * numLines(); }
  Pose2D robotPose() const { return {x_(0), x_(1), x_(2)}; }
  Eigen::Matrix3d robotCovariance() const;
  /// Line i with its 2x2 marginal covariance and its extent.
  MapLine line(size_t i) const;
  /// The 2x2 cross-covariance of the parameters of lines i and j (i != j), rows i, columns j.
  Eigen::Matrix2d lineCrossCovariance(size_t i, size_t j) const;
  /// The whole state vector (eq. 6), size stateSize().
  Eigen::VectorXd state() const { return x_.head(stateSize()); }
  /// The whole covariance (eq. 6), symmetric, stateSize() x stateSize(). Copies: not for hot paths.
  Eigen::MatrixXd covariance() const;

  /// Robot-pose NEES e^T P_rr^-1 e for a true pose (e with the angle wrapped): chi^2_3 when consistent.
  double robotNees(const Pose2D& true_pose) const;
  /// Line NEES for a true line in the place frame (either representation): chi^2_2 when consistent.
  double lineNees(size_t i, const Line& true_line) const;

  /// Replaces the whole state (e.g. from a file). `lines[i].line.cov` is ignored: the covariance is
  /// `P` (stateSize x stateSize, symmetric; its lower triangle is used). Returns false and changes
  /// nothing when the sizes disagree.
  bool setState(const Pose2D& robot, const std::vector<MapLine>& lines, const Eigen::MatrixXd& P,
                bool relocation_pending = false);

 private:
  /// Per map line, per scan: the prediction (eq. 12) and its Jacobians w.r.t. the robot and the line.
  struct LinePrediction {
    Line h;
    Matrix23d H_robot;
    Eigen::Matrix2d H_line;
    Eigen::Matrix2d HPHt;  // H P H^T over the robot and this line's blocks
  };
  /// Per observation, per scan.
  struct ObservationData {
    bool valid = false;
    Eigen::Matrix2d R = Eigen::Matrix2d::Zero();  // inflated and floored covariance
    Eigen::Vector2d start_in_place = Eigen::Vector2d::Zero();  // segment end points, through the prior pose
    Eigen::Vector2d end_in_place = Eigen::Vector2d::Zero();
    bool in_exclusion_gate = false;
  };
  struct Candidate {
    double d2;
    uint32_t observation;
    uint32_t line;
  };
  struct Extent {
    Eigen::Vector2d start, end;
  };
  /// Per match: the rows of H (eq. 15), signed for the innovation's representation.
  struct MatchJacobian {
    Matrix23d H_robot;
    Eigen::Matrix2d H_line;
    Eigen::Index line_index = 0;  // of alpha in the state
    Eigen::Matrix2d R;
  };

  size_t lineIndex(size_t i) const { return 3 + 2 * i; }
  Eigen::Matrix2d lineBlock(size_t i) const;
  void ensureLineCapacity(size_t lines);
  void ensureMatchCapacity(size_t matches);

  void prepareObservations(const std::vector<LineSegment>& observations, UpdateReport* report);
  void placeSegments(const std::vector<LineSegment>& observations, const Pose2D& sensor_pose);
  void predictLines(const SensorPose& sensor);
  bool extentsOverlap(size_t line, const ObservationData& observation) const;
  void findCandidates(const std::vector<LineSegment>& observations, const UpdateReport& report);
  void assignGreedily(UpdateReport* report);
  void summarizeMatches(UpdateReport* report) const;
  /// Keeps report->matches[first, end) whole if jointly compatible, else their individually gated
  /// part; leaves them stacked (stackInnovations). False when nothing is left to fuse.
  bool selectJointlyCompatible(const std::vector<LineSegment>& observations, size_t first, UpdateReport* report);
  /// W = P H^T, S = L L^T and L^-1 nu for report.matches[first, end) (eqs. 13–15); false when S
  /// is not positive definite.
  bool stackInnovations(const std::vector<LineSegment>& observations, size_t first, const UpdateReport& report);
  /// Eqs. 15–17 for the stacked batch.
  void applyStackedUpdate();
  /// One association pass (eqs. 12–14) for the observations not matched yet, at the current state.
  bool associate(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot, UpdateReport* report);
  RelocationResult evaluateRelocation(const UpdateReport& report) const;
  /// Map lines in range and not hidden behind an observed segment: those the scan should have shown.
  uint32_t countExpectedLines(const std::vector<LineSegment>& observations, const Pose2D& sensor_pose) const;
  void canonicalizeLine(size_t i);
  void growExtents(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot,
                   const UpdateReport& report, size_t first);
  void addNewLines(const std::vector<LineSegment>& observations, const Pose2D& sensor_in_robot,
                   UpdateReport* report);
  void addLine(const LineSegment& observation, const Eigen::Matrix2d& R, const Pose2D& sensor_in_robot);

  Params params_;
  // State (eq. 6): x_ and P_ have room for line_capacity_ lines; the first stateSize() entries /
  // rows / columns are in use, P_ in its lower triangle only.
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  size_t line_capacity_ = 0;
  std::vector<Extent> extents_;
  bool relocation_pending_ = false;

  // Work space, reused across scans.
  Eigen::MatrixXd robot_columns_;    // P_mr F^T during prediction
  Eigen::MatrixXd W_;                // P H^T, then V = W L^-T (stateSize x 2 matches)
  Eigen::MatrixXd S_;                // stacked innovation covariance, then its Cholesky factor
  Eigen::VectorXd nu_;               // stacked innovation, then L^-1 nu
  Eigen::VectorXd inv_diag_;         // 1 / L(j, j)
  double batch_nis_ = 0.0;           // (L^-1 nu)^T (L^-1 nu) of the stacked batch
  size_t batch_size_ = 0;            // matches in the stacked batch
  std::vector<LinePrediction> predictions_;
  std::vector<ObservationData> observation_data_;
  std::vector<Candidate> candidates_;
  std::vector<MatchJacobian> match_jacobians_;
  std::vector<uint8_t> line_taken_;
  UpdateReport scratch_report_;
};

}  // namespace ekf_local_map
