#include "core/io/printable.hpp"

#include <cstdio>

namespace sdfgen {

std::string printable(std::string_view text, std::size_t limit) {
    std::string out;
    auto escape = [&](unsigned char c) {
        char hex[8];
        std::snprintf(hex, sizeof hex, "\\x%02x", c);
        out += hex;
    };
    for (std::size_t i = 0; i < text.size();) {
        if (i >= limit) return out + "...";
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c == '\n') {
            out += "\\n";
        } else if (c == '\r') {
            out += "\\r";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c < 0x20 || c == 0x7F) {
            escape(c);
        } else if (c >= 0x80) {
            // A valid UTF-8 sequence is kept whole (a name in any script); any other byte is
            // escaped, so that the message is valid UTF-8 (Python decodes it).
            const std::size_t length = (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
            bool valid = length > 0 && i + length <= text.size();
            for (std::size_t k = 1; valid && k < length; ++k) valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 2;
            if (valid) {
                out.append(text.substr(i, length));
                i += length;
                continue;
            }
            escape(c);
        } else {
            out += char(c);
        }
        ++i;
    }
    return out;
}

} // namespace sdfgen
