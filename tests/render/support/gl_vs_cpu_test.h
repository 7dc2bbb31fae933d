#pragma once
// The fixture of the GL tests (tests/render/gl_*_test.cpp): one GL 3.3 compositor on a headless
// context shared by the suite (Mesa llvmpipe under xvfb-run in CI), and the CPU reference
// compositor beside it, so a test draws one request with both and compares the pictures.

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "render/compositor/cpu_compositor.h"
#include "render/gl/gl_compositor.h"

namespace hd::render::test {

class GlVsCpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    gl::WindowOptions o;
    o.headless = true;
    o.width = 64;
    o.height = 64;
    try {
      gl_ = std::make_unique<GlCompositor>(o);
    } catch (const std::exception& e) {
      error_ = e.what();
    }
  }
  static void TearDownTestSuite() { gl_.reset(); }
  void SetUp() override { ASSERT_TRUE(gl_) << "no OpenGL 3.3 core context: " << error_; }

  /// `req`, then `overlay` over it when given, by both compositors into fresh w x h pictures.
  void draw_both(const CompositeRequest& req, int w, int h, const Overlay* overlay = nullptr) {
    cpu_out_.allocate(w, h);
    gl_out_.allocate(w, h);
    cpu_.draw(req, cpu_out_);
    gl_->draw(req, gl_out_);
    if (overlay) {
      cpu_.draw_overlay(*overlay, req.viewport, cpu_out_);
      gl_->draw_overlay(*overlay, req.viewport, gl_out_);
    }
  }

  static inline std::unique_ptr<GlCompositor> gl_;
  static inline std::string error_;
  CpuCompositor cpu_{2};
  ImageRgba8 cpu_out_, gl_out_;
};

}  // namespace hd::render::test
