#pragma once
// Reading a biaxial timeseries.csv back: columns by name (comment lines skipped).
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace biaxial {

inline std::map<std::string, std::vector<double>> read_timeseries(const std::string& path) {
    std::ifstream in(path);
    std::map<std::string, std::vector<double>> columns;
    std::vector<std::string> names;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::stringstream s(line);
        std::string field;
        std::vector<std::string> fields;
        while (std::getline(s, field, ',')) fields.push_back(field);
        if (names.empty()) {
            names = fields;
            continue;
        }
        for (std::size_t i = 0; i < fields.size() && i < names.size(); ++i) columns[names[i]].push_back(std::stod(fields[i]));
    }
    return columns;
}

}  // namespace biaxial
