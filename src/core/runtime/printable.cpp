#include "core/runtime/printable.hpp"

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
            // escaped, so that the message is valid UTF-8 (Python decodes it). Valid: no overlong
            // form, no surrogate (U+D800 to U+DFFF), nothing past U+10FFFF (RFC 3629).
            const std::size_t length = c >= 0xC2 && c <= 0xDF ? 2 : (c >> 4) == 14 ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
            bool valid = length > 0 && i + length <= text.size();
            for (std::size_t k = 1; valid && k < length; ++k) valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 2;
            if (valid) {
                // The second byte's range where the first alone does not rule out what is invalid.
                const unsigned char second = static_cast<unsigned char>(text[i + 1]);
                if (c == 0xE0) valid = second >= 0xA0;      // overlong
                else if (c == 0xED) valid = second <= 0x9F; // surrogates
                else if (c == 0xF0) valid = second >= 0x90; // overlong
                else if (c == 0xF4) valid = second <= 0x8F; // past U+10FFFF
            }
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
