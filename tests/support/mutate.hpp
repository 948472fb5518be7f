#pragma once
// Random damage to a text file's contents, for the readers' fuzz loops: one to three edits among
// bit flips, cuts, repeats and inserted tokens (numbers at the edges of double, separators, BOM,
// NUL, LAMMPS section headers). Deterministic for a seeded generator.
#include <algorithm>
#include <random>
#include <string>
#include <vector>

namespace mmtest {

/// One damaged copy of `text`: one to three random edits.
inline std::string mutate(std::string text, std::mt19937_64& rng) {
    static const std::vector<std::string> inserts{",", "\n", " ", "-", "e", "1e308", "-1e308", "nan", "inf", "0", "1e-320",
                                                  "9223372036854775808", "-1", "ITEM: ATOMS id x y z radius\n",
                                                  "ITEM: NUMBER OF ATOMS\n", "\r", "#", "\xef\xbb\xbf", ";", std::string(1, '\0')};
    const int edits = 1 + static_cast<int>(rng() % 3);
    for (int e = 0; e < edits; ++e) {
        const std::size_t at = text.empty() ? 0 : rng() % (text.size() + 1);
        switch (rng() % 6) {
            case 0:  // flip one bit
                if (!text.empty()) text[std::min(at, text.size() - 1)] ^= static_cast<char>(1u << (rng() % 8));
                break;
            case 1:  // cut a range
                text.erase(at, rng() % 16);
                break;
            case 2:  // cut the end
                text.resize(at);
                break;
            case 3:  // repeat a range
                text.insert(at, text.substr(at, rng() % 40));
                break;
            default:  // insert a token
                text.insert(at, inserts[rng() % inserts.size()]);
                break;
        }
    }
    return text;
}

}  // namespace mmtest
