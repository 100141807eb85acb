#include "hsr/data_files.hpp"

#include "hsr/atomic_file.hpp"
#include "hsr/error.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfIO.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/format.h>

#include <bit>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>

static_assert(std::endian::native == std::endian::little, "the .npy and .pfm writers store the host's floats as they are");

namespace hsr {
namespace {

void write_bytes(AtomicFile& file, const void* data, size_t size) {
    if (size > 0 && std::fwrite(data, 1, size, file.stdio()) != size)
        throw Error("cannot write {}: {}", printable(file.target().string(), kMaxQuotedPathChars), std::strerror(errno));
}

void check_size(const char* what, uint32_t width, uint32_t height, uint32_t channels, size_t values) {
    if (values != size_t(width) * height * channels)
        throw Error("{}: {} values for a {}x{} image of {} channels", what, values, width, height, channels);
}

void write_npy_values(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, const char* descr,
                      const void* data, size_t bytes) {
    const std::string shape = channels == 1 ? fmt::format("({}, {})", height, width)
                                            : fmt::format("({}, {}, {})", height, width, channels);
    std::string header = fmt::format("{{'descr': '{}', 'fortran_order': False, 'shape': {}, }}", descr, shape);
    constexpr size_t preamble = 10;  // magic (6), version (2), header length (2)
    header.append(63 - (preamble + header.size()) % 64, ' ');
    header += '\n';
    const uint16_t length = uint16_t(header.size());
    const unsigned char start[preamble] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, uint8_t(length & 0xff),
                                           uint8_t(length >> 8)};
    write_bytes(file, start, preamble);
    write_bytes(file, header.data(), header.size());
    write_bytes(file, data, bytes);
}

// An OpenEXR output stream into memory, so that the file is written through the AtomicFile.
class MemoryStream : public Imf::OStream {
public:
    MemoryStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        if (position_ + size_t(n) > bytes_.size()) bytes_.resize(position_ + size_t(n));
        std::memcpy(bytes_.data() + position_, c, size_t(n));
        position_ += size_t(n);
    }
    uint64_t tellp() override { return position_; }
    void seekp(uint64_t position) override { position_ = size_t(position); }
    const std::vector<char>& bytes() const { return bytes_; }

private:
    std::vector<char> bytes_;
    size_t position_ = 0;
};

}  // namespace

void write_npy(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, std::span<const float> values) {
    check_size("write_npy", width, height, channels, values.size());
    write_npy_values(file, width, height, channels, "<f4", values.data(), values.size_bytes());
}

void write_npy(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, std::span<const int32_t> values) {
    check_size("write_npy", width, height, channels, values.size());
    write_npy_values(file, width, height, channels, "<i4", values.data(), values.size_bytes());
}

void write_pfm(AtomicFile& file, uint32_t width, uint32_t height, uint32_t channels, std::span<const float> values) {
    check_size("write_pfm", width, height, channels, values.size());
    if (channels != 1 && channels != 3) throw Error("write_pfm: {} channels (a PFM holds 1 or 3)", channels);
    const std::string header = fmt::format("{}\n{} {}\n-1.0\n", channels == 1 ? "Pf" : "PF", width, height);
    write_bytes(file, header.data(), header.size());
    const size_t row = size_t(width) * channels;
    for (uint32_t y = height; y-- > 0;) write_bytes(file, values.data() + y * row, row * sizeof(float));
}

void write_exr(AtomicFile& file, uint32_t width, uint32_t height, const std::vector<std::string>& channel_names,
               std::span<const float> values) {
    const size_t channels = channel_names.size();
    check_size("write_exr", width, height, uint32_t(channels), values.size());
    MemoryStream stream;
    try {
        Imf::Header header(static_cast<int>(width), static_cast<int>(height));
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame_buffer;
        for (size_t c = 0; c < channels; ++c) {
            header.channels().insert(channel_names[c], Imf::Channel(Imf::FLOAT));
            frame_buffer.insert(channel_names[c],
                                Imf::Slice(Imf::FLOAT, const_cast<char*>(reinterpret_cast<const char*>(values.data() + c)),
                                           sizeof(float) * channels, sizeof(float) * channels * width));
        }
        Imf::OutputFile out(stream, header, 1);
        out.setFrameBuffer(frame_buffer);
        out.writePixels(int(height));
    } catch (const std::exception& e) {
        throw Error("cannot write {}: OpenEXR: {}", printable(file.target().string(), kMaxQuotedPathChars), e.what());
    }
    write_bytes(file, stream.bytes().data(), stream.bytes().size());
}

}  // namespace hsr
