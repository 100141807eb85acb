// A stored ZIP archive (view_zip.hpp). Every file is dated 1980-01-01 00:00, the earliest date
// a ZIP can hold, so that the same files make the same archive.
#include "view/server/view_zip.hpp"

#include "hsr/error.hpp"

#include <zlib.h>

#include <limits>

namespace {

constexpr uint16_t kVersion = 20;           // 2.0: the version that reads stored files in folders
constexpr uint16_t kUtf8Names = 1u << 11;   // general purpose flag bit 11
constexpr uint16_t kDosDate = (0 << 9) | (1 << 5) | 1;  // 1980-01-01

void put16(std::string& out, uint32_t v) {
    out += char(v & 0xff);
    out += char((v >> 8) & 0xff);
}
void put32(std::string& out, uint32_t v) {
    put16(out, v & 0xffff);
    put16(out, v >> 16);
}

}  // namespace

std::string hsr::host::stored_zip(const std::vector<ZipEntry>& entries) {
    constexpr uint64_t kMax = std::numeric_limits<uint32_t>::max();
    if (entries.size() >= 0xffff) throw hsr::Error("zip: {} files; a ZIP without ZIP64 holds fewer than 65535", entries.size());
    std::string out, directory;
    for (const ZipEntry& e : entries) {
        if (e.bytes.size() > kMax || out.size() + 30 + e.name.size() + e.bytes.size() > kMax)
            throw hsr::Error("zip: the archive would be over 4 GiB");
        const uint32_t crc = uint32_t(crc32_z(crc32_z(0, nullptr, 0), e.bytes.data(), e.bytes.size()));
        const uint32_t offset = uint32_t(out.size());
        const uint32_t size = uint32_t(e.bytes.size());
        auto common = [&](std::string& to) {
            put16(to, kVersion);   // version needed to extract
            put16(to, kUtf8Names); // flags
            put16(to, 0);          // method: stored
            put16(to, 0);          // time 00:00
            put16(to, kDosDate);
            put32(to, crc);
            put32(to, size);       // compressed size
            put32(to, size);       // uncompressed size
            put16(to, uint32_t(e.name.size()));
            put16(to, 0);          // extra field length
        };
        put32(out, 0x04034b50);
        common(out);
        out += e.name;
        out.append(reinterpret_cast<const char*>(e.bytes.data()), e.bytes.size());

        put32(directory, 0x02014b50);
        put16(directory, kVersion);  // version made by: MS-DOS attributes
        common(directory);
        put16(directory, 0);  // comment length
        put16(directory, 0);  // disk number
        put16(directory, 0);  // internal attributes
        put32(directory, 0);  // external attributes
        put32(directory, offset);
        directory += e.name;
    }
    if (out.size() + directory.size() + 22 > kMax) throw hsr::Error("zip: the archive would be over 4 GiB");
    const uint32_t directory_offset = uint32_t(out.size());
    out += directory;
    put32(out, 0x06054b50);
    put16(out, 0);  // this disk
    put16(out, 0);  // the directory's disk
    put16(out, uint32_t(entries.size()));
    put16(out, uint32_t(entries.size()));
    put32(out, uint32_t(directory.size()));
    put32(out, directory_offset);
    put16(out, 0);  // comment length
    return out;
}
