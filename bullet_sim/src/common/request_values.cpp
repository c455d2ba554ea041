#include "bullet_sim/common/request_values.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace bullet_sim {

namespace {

constexpr double kMinQuaternionNorm = 1e-6;
constexpr double kMaxQuaternionNorm = 1e6;

std::string text(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace

void requireFinite(double value, const std::string& field) {
  if (!std::isfinite(value)) throw std::invalid_argument(field + " [" + text(value) + "] is not finite");
}

void requireFinite(const Eigen::Vector3d& vector, const std::string& field) {
  for (int i = 0; i < 3; ++i) requireFinite(vector[i], field + "." + "xyz"[i]);
}

void requireWithin(double value, double bound, const std::string& field, const std::string& unit) {
  requireFinite(value, field);
  if (std::abs(value) > bound) {
    const std::string units = unit.empty() ? "" : " " + unit;
    throw std::invalid_argument(field + " [" + text(value) + units + "] is beyond the " + text(bound) +
                                units + " bullet_sim takes");
  }
}

void requireWithin(const Eigen::Vector3d& vector, double bound, const std::string& field,
                   const std::string& unit) {
  for (int i = 0; i < 3; ++i) requireWithin(vector[i], bound, field + "." + "xyz"[i], unit);
}

Eigen::Quaterniond requireRotation(double x, double y, double z, double w, const std::string& field) {
  const Eigen::Quaterniond quaternion(w, x, y, z);
  const std::string shown =
      field + " (x y z w) [" + text(x) + " " + text(y) + " " + text(z) + " " + text(w) + "]";
  if (!quaternion.coeffs().allFinite()) throw std::invalid_argument(shown + " is not finite");
  if (quaternion.coeffs().isZero(0)) return Eigen::Quaterniond::Identity();
  // The largest component scales the others first, so that the norm itself neither overflows nor underflows.
  const double largest = quaternion.coeffs().cwiseAbs().maxCoeff();
  const double norm = largest * (quaternion.coeffs() / largest).norm();
  if (!(norm >= kMinQuaternionNorm && norm <= kMaxQuaternionNorm)) {
    throw std::invalid_argument(shown + " is no rotation: its norm [" + text(norm) + "] is outside [" +
                                text(kMinQuaternionNorm) + ", " + text(kMaxQuaternionNorm) +
                                "]; send a unit quaternion (all four 0 mean no rotation)");
  }
  return Eigen::Quaterniond(quaternion.coeffs() / norm);
}

}  // namespace bullet_sim
