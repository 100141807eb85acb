// A ZIP archive of files kept as they are (method 0, "stored"), for files that are compressed
// already, such as PNGs: local headers, the files' bytes, the central directory and its end record
// (PKWARE's APPNOTE.TXT 4.3), with each file's CRC-32 from zlib. No ZIP64: the archive stays under
// 4 GiB and 65535 files.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace hsr::host {

struct ZipEntry {
    std::string name;  // a relative path with '/' separators
    std::vector<uint8_t> bytes;
};

// The archive's bytes; throws hsr::Error when it would need ZIP64.
std::string stored_zip(const std::vector<ZipEntry>& entries);

}  // namespace hsr::host
