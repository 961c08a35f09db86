// Samples as NumPy .npz: a zip archive of two stored (uncompressed) .npy members, points (n, 3)
// and sdf (n,), both float32 little-endian, as numpy.savez writes them. Written to a temporary
// file beside the target and renamed over it once complete.
#include "sdfgen/error.hpp"
#include "sdfgen/sample.hpp"

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <unistd.h>

#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ != __ORDER_LITTLE_ENDIAN__
#error "the .npz writer assumes a little-endian machine"
#endif

namespace sdfgen {

namespace {

std::uint32_t crc32(std::uint32_t crc, const void* data, std::size_t size) {
    static const std::array<std::uint32_t, 256> table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    const auto* bytes = static_cast<const unsigned char*>(data);
    crc = ~crc;
    for (std::size_t i = 0; i < size; ++i) crc = table[(crc ^ bytes[i]) & 0xFF] ^ (crc >> 8);
    return ~crc;
}

// A .npy version 1.0 header for a C-order float32 array, padded to a multiple of 64 bytes.
std::string npyHeader(const std::string& shape) {
    std::string dict = "{'descr': '<f4', 'fortran_order': False, 'shape': " + shape + ", }";
    const std::size_t total = ((10 + dict.size() + 1 + 63) / 64) * 64;
    dict.append(total - 10 - dict.size() - 1, ' ');
    dict += '\n';
    std::string header = "\x93NUMPY\x01";
    header += '\0';
    header += char(dict.size() & 0xFF);
    header += char(dict.size() >> 8);
    return header + dict;
}

struct Member {
    std::string name;
    std::string header;
    const void* data;
    std::uint64_t size; // bytes after the header
    std::uint32_t crc = 0;
    std::uint64_t offset = 0;
};

void put16(std::string& out, std::uint32_t v) { out.append({char(v & 0xFF), char((v >> 8) & 0xFF)}); }
void put32(std::string& out, std::uint32_t v) { put16(out, v & 0xFFFF), put16(out, v >> 16); }
void put64(std::string& out, std::uint64_t v) { put32(out, std::uint32_t(v)), put32(out, std::uint32_t(v >> 32)); }

// Local and central headers with ZIP64 sizes and offsets, so members of any size are valid.
std::string localHeader(const Member& m) {
    std::string h;
    put32(h, 0x04034b50);
    put16(h, 45); // version needed: ZIP64
    put16(h, 0x0800); // UTF-8 names
    put16(h, 0);      // stored
    put32(h, 0x00210000); // 1980-01-01 00:00: reproducible archives
    put32(h, m.crc);
    put32(h, 0xFFFFFFFF);
    put32(h, 0xFFFFFFFF);
    put16(h, std::uint32_t(m.name.size()));
    put16(h, 20);
    h += m.name;
    put16(h, 0x0001);
    put16(h, 16);
    put64(h, m.header.size() + m.size);
    put64(h, m.header.size() + m.size);
    return h;
}

std::string centralDirectory(const std::vector<Member>& members, std::uint64_t start) {
    std::string d;
    for (const Member& m : members) {
        put32(d, 0x02014b50);
        put16(d, 45);
        put16(d, 45);
        put16(d, 0x0800);
        put16(d, 0);
        put32(d, 0x00210000);
        put32(d, m.crc);
        put32(d, 0xFFFFFFFF);
        put32(d, 0xFFFFFFFF);
        put16(d, std::uint32_t(m.name.size()));
        put16(d, 28);
        put16(d, 0);
        put16(d, 0);
        put16(d, 0);
        put32(d, 0);
        put32(d, 0xFFFFFFFF);
        d += m.name;
        put16(d, 0x0001);
        put16(d, 24);
        put64(d, m.header.size() + m.size);
        put64(d, m.header.size() + m.size);
        put64(d, m.offset);
    }
    const std::uint64_t size = d.size();
    const std::uint64_t zip64End = start + size;
    put32(d, 0x06064b50); // ZIP64 end of central directory
    put64(d, 44);
    put16(d, 45);
    put16(d, 45);
    put32(d, 0);
    put32(d, 0);
    put64(d, members.size());
    put64(d, members.size());
    put64(d, size);
    put64(d, start);
    put32(d, 0x07064b50); // its locator
    put32(d, 0);
    put64(d, zip64End);
    put32(d, 1);
    put32(d, 0x06054b50); // end of central directory
    put16(d, 0);
    put16(d, 0);
    put16(d, 0xFFFF);
    put16(d, 0xFFFF);
    put32(d, 0xFFFFFFFF);
    put32(d, 0xFFFFFFFF);
    put16(d, 0);
    return d;
}

} // namespace

void saveSamples(const Samples& samples, const std::string& path) {
    const std::size_t n = samples.size();
    if (samples.points.size() != 3 * n) throw Error(path + ": samples have " + std::to_string(samples.points.size()) + " coordinates for " + std::to_string(n) + " points");
    std::vector<Member> members = {
        {"points.npy", npyHeader("(" + std::to_string(n) + ", 3)"), samples.points.data(), 3 * n * sizeof(float)},
        {"sdf.npy", npyHeader("(" + std::to_string(n) + ",)"), samples.sdf.data(), n * sizeof(float)}};
    const std::string temporary = path + ".partial-" + std::to_string(getpid());
    std::FILE* file = std::fopen(temporary.c_str(), "wb");
    if (!file) throw Error(path + ": cannot write: " + std::strerror(errno));
    bool ok = true;
    auto write = [&](const void* data, std::size_t size) { ok = ok && std::fwrite(data, 1, size, file) == size; };
    std::uint64_t offset = 0;
    for (Member& m : members) {
        m.crc = crc32(crc32(0, m.header.data(), m.header.size()), m.data, m.size);
        m.offset = offset;
        const std::string local = localHeader(m);
        write(local.data(), local.size());
        write(m.header.data(), m.header.size());
        write(m.data, m.size);
        offset += local.size() + m.header.size() + m.size;
    }
    const std::string directory = centralDirectory(members, offset);
    write(directory.data(), directory.size());
    const int writeError = errno;
    ok = std::fflush(file) == 0 && ok && fsync(fileno(file)) == 0;
    ok = std::fclose(file) == 0 && ok;
    if (!ok || std::rename(temporary.c_str(), path.c_str()) != 0) {
        const std::string why = std::strerror(ok ? errno : writeError);
        std::remove(temporary.c_str());
        throw Error(path + ": cannot write: " + why);
    }
}

} // namespace sdfgen
