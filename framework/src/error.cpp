// The error types' helpers (error.hpp): which errors are the asker's, and printable(), user text
// made safe to quote in a one-line error message.
#include "hsr/error.hpp"

#include <cstdint>

namespace hsr {
namespace {

// The length of the well-formed UTF-8 sequence starting text[at] (Unicode 15, table 3-7) and the
// code point it encodes; length 0 when the bytes there are not one.
std::size_t utf8_sequence(std::string_view text, std::size_t at, uint32_t& code_point) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[at + k]); };
    const unsigned char lead = byte(0);
    std::size_t length = 0;
    unsigned char low = 0x80, high = 0xBF;  // the allowed range of the second byte
    if (lead < 0x80) {
        code_point = lead;
        return 1;
    } else if (lead >= 0xC2 && lead <= 0xDF) {
        length = 2;
        code_point = lead & 0x1F;
    } else if (lead >= 0xE0 && lead <= 0xEF) {
        length = 3;
        code_point = lead & 0x0F;
        if (lead == 0xE0) low = 0xA0;
        if (lead == 0xED) high = 0x9F;  // no surrogates
    } else if (lead >= 0xF0 && lead <= 0xF4) {
        length = 4;
        code_point = lead & 0x07;
        if (lead == 0xF0) low = 0x90;
        if (lead == 0xF4) high = 0x8F;  // nothing above U+10FFFF
    } else {
        return 0;
    }
    if (at + length > text.size()) return 0;
    for (std::size_t k = 1; k < length; ++k) {
        const unsigned char b = byte(k);
        if (b < (k == 1 ? low : 0x80) || b > (k == 1 ? high : 0xBF)) return 0;
        code_point = (code_point << 6) | (b & 0x3F);
    }
    return length;
}

bool is_control(uint32_t c) { return c < 0x20 || (c >= 0x7F && c <= 0x9F) || c == 0x2028 || c == 0x2029; }

}  // namespace

bool plugin_refused_input(hsr_status status) {
    return status == HSR_ERROR_INVALID_ARGUMENT || status == HSR_ERROR_UNSUPPORTED;
}

bool is_client_error(const Error& error) {
    if (dynamic_cast<const UsageError*>(&error) != nullptr || dynamic_cast<const LimitError*>(&error) != nullptr)
        return true;
    const auto* plugin = dynamic_cast<const PluginError*>(&error);
    return plugin != nullptr && plugin_refused_input(plugin->status);
}

void rethrow_with_message(const Error& error, const std::string& message) {
    if (dynamic_cast<const UsageError*>(&error) != nullptr) throw UsageError(message);
    if (dynamic_cast<const LimitError*>(&error) != nullptr) throw LimitError(message);
    if (const auto* plugin = dynamic_cast<const PluginError*>(&error)) throw PluginError(plugin->status, message);
    throw Error(message);
}

std::string printable(std::string_view text, std::size_t max_chars) {
    std::string out;
    std::size_t at = 0;
    for (std::size_t chars = 0; at < text.size(); ++chars) {
        if (chars == max_chars) {
            out += "...";
            break;
        }
        uint32_t code_point = 0;
        const std::size_t length = utf8_sequence(text, at, code_point);
        if (length == 0) {
            out += fmt::format("\\x{:02x}", static_cast<unsigned char>(text[at]));
            ++at;
        } else if (is_control(code_point)) {
            out += code_point < 0x100 ? fmt::format("\\x{:02x}", code_point) : fmt::format("\\u{:04x}", code_point);
            at += length;
        } else {
            out.append(text, at, length);
            at += length;
        }
    }
    return out;
}

}  // namespace hsr
