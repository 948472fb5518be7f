#pragma once
// Reading a biaxial timeseries.csv back: columns by name (comment lines skipped); and the few
// statistics biaxial_summary takes of a column.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace biaxial {

/// The columns of a timeseries.csv by name. A damaged file is an error naming the file and line:
/// no header, a repeated column name, a row with another number of fields than the header, or a
/// field that is not a finite number (the biaxial program writes none).
inline std::map<std::string, std::vector<double>> read_timeseries(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    std::map<std::string, std::vector<double>> columns;
    std::vector<std::string> names;
    std::string line;
    auto fail = [&](std::size_t number, const std::string& what) {
        throw std::runtime_error(path + ":" + std::to_string(number) + ": " + what);
    };
    for (std::size_t number = 1; std::getline(in, line); ++number) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (line.empty() || line[0] == '#') continue;
        std::vector<std::string> fields;
        std::stringstream s(line);
        for (std::string field; std::getline(s, field, ',');) fields.push_back(field);
        if (line.back() == ',') fields.emplace_back();
        if (names.empty()) {
            names = fields;
            for (const auto& name : names)
                if (name.empty() || !columns.emplace(name, std::vector<double>{}).second)
                    fail(number, "the header names column '" + name + "' " + (name.empty() ? "without a name" : "twice"));
            continue;
        }
        if (fields.size() != names.size())
            fail(number, std::to_string(fields.size()) + " fields where the header has " + std::to_string(names.size()));
        for (std::size_t i = 0; i < fields.size(); ++i) {
            const std::string& f = fields[i];
            double v = 0.0;
            const auto [end, error] = std::from_chars(f.data(), f.data() + f.size(), v);
            if (error != std::errc() || end != f.data() + f.size() || !std::isfinite(v))
                fail(number, "column '" + names[i] + "' holds '" + f + "', not a finite number");
            columns[names[i]].push_back(v);
        }
    }
    if (in.bad()) throw std::runtime_error("cannot read " + path);
    if (names.empty()) throw std::runtime_error(path + " has no header line: not a biaxial time series");
    return columns;
}

/// The p-quantile (0 <= p <= 1) of `values` by the lower nearest rank: the element at
/// floor(p (n - 1)) of the sorted values. NaN for no values.
inline double quantile(std::vector<double> values, double p) {
    if (values.empty()) return NAN;
    const auto k = static_cast<std::size_t>(std::floor(p * double(values.size() - 1)));
    std::nth_element(values.begin(), values.begin() + k, values.end());
    return values[k];
}

/// The centred running mean of `v` over `width` rows (odd), over fewer rows at the ends.
inline std::vector<double> running_mean(const std::vector<double>& v, int width) {
    const auto half = static_cast<std::ptrdiff_t>(width / 2), n = static_cast<std::ptrdiff_t>(v.size());
    std::vector<double> mean(v.size());
    for (std::ptrdiff_t r = 0; r < n; ++r) {
        const std::ptrdiff_t lo = std::max<std::ptrdiff_t>(0, r - half), hi = std::min(n, r + half + 1);
        double sum = 0.0;
        for (std::ptrdiff_t k = lo; k < hi; ++k) sum += v[k];
        mean[r] = sum / double(hi - lo);
    }
    return mean;
}

/// How often `v` rises through `level` (a running mean, say) in rows first+1 .. last: row r
/// counts when v[r - 1] < level[r - 1] and v[r] >= level[r].
inline int upward_crossings(const std::vector<double>& v, const std::vector<double>& level, std::size_t first, std::size_t last) {
    int count = 0;
    for (std::size_t r = first + 1; r <= last && r < v.size(); ++r) count += v[r - 1] < level[r - 1] && v[r] >= level[r];
    return count;
}

}  // namespace biaxial
