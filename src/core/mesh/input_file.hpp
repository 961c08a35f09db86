#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

namespace sdfgen {

// The most bytes an input file may have: SDFGEN_MAX_INPUT_MB (mebibytes) when set, else 4 GiB.
// A bound, so that /dev/zero or an endless pipe given as input fails at once instead of eating memory.
std::uint64_t maxInputBytes();

enum class InputKind { Binary, Text };

// Reads a whole file into memory: regular files, pipes, FIFOs and devices alike (/dev/stdin).
// Throws Error("PATH: problem") when it cannot be opened or read, is a directory, or is larger than
// maxBytes (checked before reading for a regular file, while reading otherwise). For Text, a NUL
// byte is refused as it arrives ("PATH:LINE: NUL byte ..."). `onRead`, when given, is called with
// each block's byte count as it arrives (a reader's progress and cancel).
std::string readInputFile(const std::string& path, InputKind kind, std::uint64_t maxBytes = maxInputBytes(),
                          const std::function<void(std::size_t)>& onRead = {});

// `text` without a leading UTF-8 byte-order mark: what every reader of a text format (OBJ, PLY's
// header, OFF, ASCII STL, glTF's JSON, the sdfgen-text field) skips.
std::string_view withoutByteOrderMark(std::string_view text);

// The number of the line (from 1) that byte `offset` of `text` lies on; \n, \r\n and a lone \r
// each end a line.
std::size_t lineNumberAt(const std::string& text, std::size_t offset);

} // namespace sdfgen
