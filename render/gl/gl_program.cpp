#include "render/gl/gl_program.h"

#include <stdexcept>
#include <string>

namespace hd::render::gl {
namespace {

GLuint compile(GLenum type, const char* source, const char* name) {
  const GLuint shader = glCreateShader(type);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("GL compositor: shader ") + name + " failed: " + log);
  }
  return shader;
}

}  // namespace

Program link_program(const char* vs, const char* fs, const char* name) {
  Program program = Program::create();
  const GLuint v = compile(GL_VERTEX_SHADER, vs, name);
  GLuint f = 0;
  try {
    f = compile(GL_FRAGMENT_SHADER, fs, name);
  } catch (...) {
    glDeleteShader(v);
    throw;
  }
  glAttachShader(program.get(), v);
  glAttachShader(program.get(), f);
  glLinkProgram(program.get());
  glDeleteShader(v);  // flagged; freed with the program
  glDeleteShader(f);
  GLint ok = 0;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
  if (!ok) {
    char log[2048] = {};
    glGetProgramInfoLog(program.get(), sizeof log, nullptr, log);
    throw std::runtime_error(std::string("GL compositor: program ") + name +
                             " link failed: " + log);
  }
  return program;
}

}  // namespace hd::render::gl
