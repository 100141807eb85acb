// Mutated copies of model and scene files, for the robustness test (tests/mutated_inputs.sh): each
// mutant is a seed file changed in one to four places, in the ways that broke readers before —
// numbers replaced by extremes (2^63 - 1, -2^63, 1e309, nan), lines repeated many times, bytes
// flipped, inserted, cut or duplicated, the file truncated. The same seed number gives the same files.
//
//   mutate_inputs <out dir> <count> <seed number> <seed file>...
//
// The seed files are copied into <out dir> under their own names (so that a .scene file's mesh
// lines still find them), then <count> mutants are written as mutant-NNNNN.<seed's extension>.
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <string_view>
#include <vector>

namespace fs = std::filesystem;

namespace {

// A line of a binary file may be the whole file: its copies stop at this many bytes.
constexpr std::size_t max_repeated_bytes = 1 << 20;

constexpr std::array<std::string_view, 16> extreme_numbers = {
    "0",   "-1",  "-0",     "2147483647", "4294967296", "9223372036854775807", "-9223372036854775808",
    "1e309", "-1e309", "nan", "inf", "1e-320", "99999999999999999999999", "3.4028236e38", "0x10", "1e38"};

class Mutator {
public:
    explicit Mutator(unsigned seed) : random_(seed) {}

    std::string mutate(std::string text) {
        const int changes = pick(1, 4);
        for (int k = 0; k < changes; ++k) {
            switch (pick(0, 7)) {
            case 0: replace_number(text); break;
            case 1: repeat_line(text); break;
            case 2: flip_bits(text); break;
            case 3: insert_bytes(text); break;
            case 4: cut_range(text); break;
            case 5: duplicate_range(text); break;
            case 6: swap_lines(text); break;
            default: text.resize(position(text)); break;  // truncated
            }
        }
        return text;
    }

private:
    int pick(int low, int high) { return std::uniform_int_distribution<int>(low, high)(random_); }
    std::size_t position(const std::string& text) {
        return std::uniform_int_distribution<std::size_t>(0, text.size())(random_);
    }

    // The span [begin, end) of the line holding byte `at`.
    static std::pair<std::size_t, std::size_t> line_around(const std::string& text, std::size_t at) {
        const std::size_t begin = at == 0 ? 0 : text.rfind('\n', at - 1) + 1;  // npos + 1 == 0
        const std::size_t newline = text.find('\n', at);
        return {begin, newline == std::string::npos ? text.size() : newline + 1};
    }

    void replace_number(std::string& text) {
        std::vector<std::size_t> starts;  // where a run of digits, '-' or '.' begins
        for (std::size_t i = 0; i < text.size(); ++i) {
            const bool in_number = std::isdigit(static_cast<unsigned char>(text[i])) || text[i] == '-' || text[i] == '.';
            const bool after_number = i > 0 && (std::isdigit(static_cast<unsigned char>(text[i - 1])) ||
                                                text[i - 1] == '-' || text[i - 1] == '.');
            if (in_number && !after_number) starts.push_back(i);
        }
        if (starts.empty()) return;
        const std::size_t begin = starts[std::uniform_int_distribution<std::size_t>(0, starts.size() - 1)(random_)];
        std::size_t end = begin;
        while (end < text.size() && (std::isdigit(static_cast<unsigned char>(text[end])) || text[end] == '-' ||
                                     text[end] == '.' || text[end] == 'e'))
            ++end;
        text.replace(begin, end - begin, extreme_numbers[pick(0, int(extreme_numbers.size()) - 1)]);
    }

    void repeat_line(std::string& text) {
        if (text.empty()) return;
        const auto [begin, end] = line_around(text, position(text) % text.size());
        const std::string line = text.substr(begin, end - begin);
        std::string repeated;
        for (int k = pick(2, 2000); k > 0 && repeated.size() < max_repeated_bytes; --k) repeated += line;
        text.insert(end, repeated);
    }

    void flip_bits(std::string& text) {
        if (text.empty()) return;
        for (int k = pick(1, 8); k > 0; --k) text[position(text) % text.size()] ^= char(1 << pick(0, 7));
    }

    void insert_bytes(std::string& text) {
        std::string bytes;
        for (int k = pick(1, 16); k > 0; --k) bytes += char(pick(0, 255));
        text.insert(position(text), bytes);
    }

    void cut_range(std::string& text) {
        const std::size_t begin = position(text);
        text.erase(begin, std::min<std::size_t>(text.size() - begin, std::size_t(pick(1, 256))));
    }

    void duplicate_range(std::string& text) {
        const std::size_t begin = position(text);
        const std::string range = text.substr(begin, std::size_t(pick(1, 512)));
        text.insert(position(text), range);
    }

    void swap_lines(std::string& text) {
        if (text.empty()) return;
        auto [a_begin, a_end] = line_around(text, position(text) % text.size());
        auto [b_begin, b_end] = line_around(text, position(text) % text.size());
        if (a_begin == b_begin) return;
        if (b_begin < a_begin) {
            std::swap(a_begin, b_begin);
            std::swap(a_end, b_end);
        }
        if (a_end > b_begin) return;
        const std::string a = text.substr(a_begin, a_end - a_begin), b = text.substr(b_begin, b_end - b_begin);
        text.replace(b_begin, b.size(), a);
        text.replace(a_begin, a.size(), b);
    }

    std::mt19937 random_;
};

std::string slurp(const fs::path& file) {
    std::ifstream in(file, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 5) {
        std::cerr << "usage: mutate_inputs <out dir> <count> <seed number> <seed file>...\n";
        return 2;
    }
    const fs::path out = argv[1];
    const long count = std::strtol(argv[2], nullptr, 10);
    const auto seed = static_cast<unsigned>(std::strtoul(argv[3], nullptr, 10));
    std::vector<fs::path> seeds(argv + 4, argv + argc);
    std::vector<std::string> texts;
    fs::create_directories(out);
    for (const fs::path& file : seeds) {
        texts.push_back(slurp(file));
        if (texts.back().empty()) {
            std::cerr << "mutate_inputs: cannot read " << file << "\n";
            return 1;
        }
        fs::copy_file(file, out / file.filename(), fs::copy_options::overwrite_existing);
    }
    Mutator mutator(seed);
    std::mt19937 choose(seed + 1);
    for (long k = 0; k < count; ++k) {
        const std::size_t which = std::uniform_int_distribution<std::size_t>(0, seeds.size() - 1)(choose);
        char name[32];
        std::snprintf(name, sizeof name, "mutant-%05ld", k);
        std::ofstream(out / (name + seeds[which].extension().string()), std::ios::binary) << mutator.mutate(texts[which]);
    }
    return 0;
}
