#pragma once
/// A trajectory from anywhere (docs/report-format.md, "Outside runs"): a CSV
/// of joint coordinates or of body poses that another simulator, a script or
/// eigenmass itself wrote, read against a scene and judged like a run. The
/// file is read and checked once, before any run; its samples are put on
/// each comparison's grid when asked (recordedTrajectory).
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "solver/trajectory.hpp"

namespace em {

/// A recorded run's first sample must be the scene's initial state within
/// this (rad, m; a quaternion's components): a float32 log holds ~1e-7.
constexpr double kRecordedStartTol = 1e-6;
/// A logged quaternion's norm must be 1 within this.
constexpr double kRecordedUnitTol = 1e-6;
/// Samples in the difference that gives a body-poses file's speeds: five,
/// fourth order in the spacing (three, central, is second order and inflated a
/// 10-ms log's energy error from 0.0945 to 0.117; issue 53 item 19).
constexpr size_t kSpeedPoints = 5;

/// The file as read: samples in the model's internal order.
struct RecordedRun {
  std::string name, file, sha256;
  std::string format;   ///< "joint-coordinates" or "body-poses"
  std::string speeds;   ///< where u came from: "file" or "central differences"
  std::map<std::string, std::string> declared;  ///< the "# key: value" lines before the header
  double cpu_s = 0;     ///< declared cpu_s (0 when not declared)
  std::vector<double> t;
  std::vector<Eigen::VectorXd> q, u;          ///< internal order  // (nq), (nu) per sample
  std::vector<std::vector<Pose>> poses;       ///< body poses as logged, internal order (body-poses only)
  std::vector<double> dissipated;             ///< W_diss: the file's `dissipated` column, else the trapezoid rule over the samples
  std::string dissipated_from;                ///< which of the two (the report's source.dissipated)
  double max_joint_separation = 0;            ///< body-poses: the largest distance between a joint's two points (m)
  /// Speeds by differences: max |T(5-point u) - T(3-point u)| / max T, the
  /// second-order estimate's error that the spacing puts on the energy figure
  /// (the five-point one's is smaller by O(h^2)); 0 when the file gives speeds.
  double spacing_effect = 0;
};

/// Read `path` as run `name` of the scene `m`: one line naming the file, the
/// line and the column for a defect (std::invalid_argument). Adds a method
/// row named `name` and returns its id.
Method addRecordedRun(const std::string& name, const std::string& path, const Model& m);

/// The scheme row of every recorded run, "recorded" (added once; in-house
/// runs are refused it: no code of ours steps it).
Integrator recordedScheme();

/// The recorded run of method `method`, or nullptr for any other method.
const RecordedRun* recordedRun(Method method);

/// Its samples on the grid of `spec` (t_end, output_dt): taken where a sample
/// lies on a grid time, else interpolated linearly (quaternions normalized);
/// a file that ends before t_end is an ended-early failure at its last time.
Trajectory recordedTrajectory(const Model& m, const CheckedRunSpec& spec);

/// Where it came from, for its report: file, SHA-256, format, speeds, the
/// interpolation, and what the file declared.
nlohmann::json recordedSource(Method method);

}  // namespace em
