#version 450 core
// The exact distance signed by the closest feature's pseudonormal (shaders/nearest.glsl).
#define SIGN_BY_PSEUDONORMAL 1
#include "nearest.glsl"
