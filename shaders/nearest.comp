#version 450 core
// The exact unsigned distance (shaders/nearest.glsl), for the winding sign or none.
#define SIGN_BY_PSEUDONORMAL 0
#include "nearest.glsl"
