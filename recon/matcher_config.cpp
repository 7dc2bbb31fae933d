#include "recon/matcher_config.h"

#include <cmath>
#include <stdexcept>

namespace hd::recon {

std::string_view to_string(MatcherKind k) {
  switch (k) {
    case MatcherKind::kSgbmScaled:
      return "sgbm-scaled";
    case MatcherKind::kSgbm:
      return "sgbm";
    case MatcherKind::kBm:
      return "bm";
  }
  return "?";
}

MatcherKind matcher_kind_from_string(std::string_view s) {
  for (MatcherKind k : {MatcherKind::kSgbmScaled, MatcherKind::kSgbm, MatcherKind::kBm})
    if (s == to_string(k)) return k;
  throw std::invalid_argument("unknown matcher '" + std::string(s) +
                              "' (expected sgbm-scaled, sgbm or bm)");
}

void MatcherConfig::check() const {
  auto bad = [](const std::string& field, const std::string& what) {
    throw std::invalid_argument("matcher." + field + ": " + what);
  };
  if (min_disparity_px < 1)
    bad("min_disparity_px", "must be >= 1 (disparity 0 is a point at infinity)");
  if (num_disparities_px < 16 || num_disparities_px > 1024)
    bad("num_disparities_px", "must be in 16..1024");
  if (!(scale >= 0.25 && scale <= 1.0)) bad("scale", "must be in 0.25..1");
  if (block_size_px != 0 && (block_size_px < 1 || block_size_px > 31 || block_size_px % 2 == 0))
    bad("block_size_px", "must be 0 (default) or odd in 1..31");
  if (kind == MatcherKind::kBm && block_size_px != 0 && block_size_px < 5)
    bad("block_size_px", "StereoBM needs an odd block of at least 5");
  if (uniqueness_percent < 0 || uniqueness_percent > 100)
    bad("uniqueness_percent", "must be in 0..100");
}

}  // namespace hd::recon
