#pragma once
// A field as a bake gives it (BakeResult::field) or a file holds it (loadAnyField): dense (Field)
// or narrow band (SparseField), exactly one of the two. Front ends ask it which it is, rather than
// the settings that made it or the file's format, and take the field as it is: a band field is
// never made dense unless a front end asks for that (SparseField::toDense).
#include "sdfgen/field.hpp"
#include "sdfgen/sparse_field.hpp"

#include <utility>
#include <variant>

namespace sdfgen {

class AnyField {
public:
    AnyField() = default; // an empty dense field, to be assigned
    AnyField(Field field) : field_(std::move(field)) {}
    AnyField(SparseField field) : field_(std::move(field)) {}

    // Whether it is a narrow-band field (band()), not a dense one (dense()).
    bool isBand() const { return std::holds_alternative<SparseField>(field_); }
    // The field as what it is; asking for the other kind throws std::bad_variant_access.
    const Field& dense() const { return std::get<Field>(field_); }
    Field& dense() { return std::get<Field>(field_); }
    const SparseField& band() const { return std::get<SparseField>(field_); }
    SparseField& band() { return std::get<SparseField>(field_); }
    // What both kinds have: the grid, the names and the background (0 for a dense field of distances only).
    const FieldHeader& header() const { return isBand() ? band().header() : dense(); }

    // visit(f) calls f(field) with the Field or the SparseField.
    template <class Visitor>
    decltype(auto) visit(Visitor&& visitor) const {
        return std::visit(std::forward<Visitor>(visitor), field_);
    }

private:
    std::variant<Field, SparseField> field_;
};

} // namespace sdfgen
