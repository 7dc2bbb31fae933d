#include "core/blend_weights.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace hd::core {

double video_weight(double m, double m_t, double eps) {
  if (std::isnan(m) || std::isnan(m_t) || !std::isfinite(eps) || eps < 0.0) return 0.0;
  if (m == std::numeric_limits<double>::infinity()) return 0.0;
  if (eps == 0.0) return m <= m_t ? 1.0 : 0.0;
  const double w = (m_t + eps - m) / (2.0 * eps);
  return std::isnan(w) ? 0.0 : std::clamp(w, 0.0, 1.0);
}

double pixel_weight(double kappa, double u, double v, double width, double height) {
  if (std::isnan(kappa) || std::isnan(u) || std::isnan(v) || !(width > 0.0) || !(height > 0.0) ||
      !std::isfinite(width) || !std::isfinite(height))
    return 0.0;
  kappa = std::clamp(kappa, 0.0, 1.0);
  if (kappa == 0.0) return 1.0;
  const double x = std::min(std::abs(1.0 - 2.0 * u / width), 1.0);
  const double y = std::min(std::abs(1.0 - 2.0 * v / height), 1.0);
  const double inner = 1.0 - kappa;
  double w;
  if (x <= inner && y <= inner) {
    w = 1.0;
  } else if (x > inner && y <= inner) {
    w = (1.0 - x) / kappa;
  } else if (x <= inner && y > inner) {
    w = (1.0 - y) / kappa;
  } else {
    w = 1.0 - std::hypot(x - inner, y - inner) / kappa;
  }
  w = std::clamp(w, 0.0, 1.0);
  return (std::sin((w - 0.5) * std::numbers::pi) + 1.0) / 2.0;
}

double continuous_pixel_weight(double w_video, double u, double v, double width, double height) {
  if (std::isnan(w_video)) return 0.0;
  w_video = std::clamp(w_video, 0.0, 1.0);
  const double strength = std::min(1.0, 2.0 * w_video);
  const double kappa = std::min(1.0, 2.0 * (1.0 - w_video));
  return strength * pixel_weight(kappa, u, v, width, height);
}

}  // namespace hd::core
