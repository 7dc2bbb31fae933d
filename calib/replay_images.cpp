#include "calib/replay_images.h"

#include "calib/image_set.h"

namespace hd::calib {

std::vector<drivers::ReplayImage> load_replay_images(const drivers::ReplayId& id) {
  std::vector<drivers::ReplayImage> out;
  for (const NamedImage& im : load_image_set(id.folder, id.pattern)) {
    drivers::ReplayImage ri;
    ri.name = im.name;
    ri.width = im.gray.cols;
    ri.height = im.gray.rows;
    const cv::Mat packed = im.gray.isContinuous() ? im.gray : im.gray.clone();
    ri.gray.assign(packed.datastart, packed.dataend);
    out.push_back(std::move(ri));
  }
  return out;
}

}  // namespace hd::calib
