#pragma once
// A GL program from GLSL vertex and fragment sources (render/gl/shaders/, embedded at build time),
// with the driver's log in the error when a stage does not compile or link.

#include "render/gl/gl_objects.h"

namespace hd::render::gl {

/// Compiles both stages and links them; the shaders are freed with the program. Throws
/// std::runtime_error naming `name` and the stage, with the driver's info log. Needs a current
/// context.
Program link_program(const char* vertex_source, const char* fragment_source, const char* name);

}  // namespace hd::render::gl
