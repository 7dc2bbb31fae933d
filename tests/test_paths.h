#pragma once
// Where the tests find the checkout, the shared data and the built programs.
//
// The answers are compiled into one generated file per build (tests/test_paths.cpp.in), never into
// a test's own object: an absolute path in a compile definition made every test object differ
// between two clones, so a fresh clone recompiled every test even with a warm compiler cache.
namespace hd::test {

const char* source_dir();       ///< the checkout (scenes/, render/lens/profiles/, remote/)
const char* calib_data_dir();   ///< shared/data/calib beside the checkout
const char* stereo_data_dir();  ///< shared/data/stereo beside the checkout
const char* station_bin();      ///< the built hybrid-station
const char* remote_bin();       ///< the built hybrid-remote
const char* calib_bin();        ///< the built hybrid-calib
const char* recon_bin();        ///< the built hybrid-recon
const char* geom_bin();         ///< the built hybrid-geom

}  // namespace hd::test
