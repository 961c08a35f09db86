#pragma once
#include "sdfgen/field.hpp"
#include "sdfgen/mesh.hpp"

#include <string>

namespace sdfgen {

// Why `field` may not be the field of `mesh`, for a warning: it was made from a file of another
// name, its grid does not cover the mesh's bounding box, or both (both said). Empty when neither.
std::string fieldMismatch(const FieldHeader& field, const Mesh& mesh);

} // namespace sdfgen
