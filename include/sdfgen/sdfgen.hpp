#pragma once
// The sdfgen library in one include: meshes in, signed distance fields and point queries out.
#include "sdfgen/bake.hpp"
#include "sdfgen/compare.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/field.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/grid.hpp"
#include "sdfgen/mesh.hpp"
#include "sdfgen/mesh_check.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/run_control.hpp"
#include "sdfgen/sample.hpp"
