// The HUD strip's texels, blended by their alpha (the blend state is set by the caller).
#version 330 core
uniform sampler2D strip;
uniform vec2 origin;
out vec4 colour;
void main() { colour = texelFetch(strip, ivec2(gl_FragCoord.xy - origin), 0); }
