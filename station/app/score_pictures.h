#pragma once
// The score run's error pictures: a per-pixel error map of a shown picture against its truth, on
// a fixed colour scale, and a contact sheet of rows shown | truth | error, so a reader sees where
// the PSNR of score.csv comes from.

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "render/compositor/image_rgba8.h"

namespace hd::station {

/// The error that saturates the map (digital numbers, DN). Fixed, not per picture, so maps of
/// different frames compare: the same colour is the same error everywhere.
inline constexpr int kErrorMapFullScaleDn = 64;

/// BGR 8-bit, the size of the inputs. Per pixel e = max over R, G, B of |shown - truth| (alpha
/// ignored), drawn with OpenCV's INFERNO map at index round(min(e, 64) * 255 / 64): 0 DN is
/// the map's zero colour (near black), 64 DN and more its top colour (pale yellow).
/// Two empty pictures give an empty map; pictures of different sizes throw
/// std::invalid_argument naming both sizes.
cv::Mat error_map(const render::ImageRgba8& shown, const render::ImageRgba8& truth);

/// The colour of an error of `dn` DN on the map (saturating at kErrorMapFullScaleDn).
cv::Vec3b error_colour_bgr(int dn);

/// The scale bar for error_map: `width_px` x 36 BGR, the colour ramp from 0 to 64 DN with ticks
/// every 16 DN and what e is. Stack it under a map with cv::vconcat for a map that explains
/// itself. Throws std::invalid_argument below 64 px.
cv::Mat error_legend(int width_px);

/// One row of the contact sheet: a label (e.g. "frame 120 eye 0 hybrid 28.4 dB") and three BGR
/// 8-bit pictures. An empty picture is drawn as a grey tile.
struct SheetRow {
  std::string label;
  cv::Mat shown, truth, error;
};

/// The widest sheet score_contact_sheet draws; wider pictures are scaled down to fit.
inline constexpr int kSheetMaxWidthPx = 2000;

/// One BGR picture: column titles "shown", "truth", "error", then per row its label over the
/// three pictures, then error_legend under the error column. Every tile has the size of the
/// first row's first non-empty picture, scaled down (never up; INTER_AREA) so the sheet is at
/// most kSheetMaxWidthPx wide; other pictures are fitted into it keeping their aspect ratio.
/// Throws std::invalid_argument when there is no row, no row has a picture, or a picture is not
/// CV_8UC3.
cv::Mat score_contact_sheet(const std::vector<SheetRow>& rows);

}  // namespace hd::station
