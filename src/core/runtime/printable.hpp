#pragma once
// Text taken from a file, as it may appear in a one-line error message: control bytes and DEL
// escaped (\n, \r, \t, \xNN), valid UTF-8 kept and any other byte escaped, and cut to `limit`
// bytes with "..." after. Every reader, of fields and of meshes, quotes file text through this.
#include <cstddef>
#include <string>
#include <string_view>

namespace sdfgen {

std::string printable(std::string_view text, std::size_t limit = 60);

} // namespace sdfgen
