#include "ifsforge/io/fractint.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "ifsforge/core/error.h"
#include "ifsforge/core/memory.h"
#include "ifsforge/io/text_file.h"

namespace ifsforge {
namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

struct Pending {
  std::string name;
  int line = 0;
  bool three_d = false;
  std::vector<AffineMap> maps;
  std::vector<double> probabilities;
};

}  // namespace

std::vector<Ifs> parse_fractint(const std::string& text, const std::string& source) {
  std::vector<Ifs> systems;
  std::istringstream lines(text);
  std::string raw;
  int line_no = 0;
  bool inside = false;
  std::string name_so_far;
  Pending entry;
  auto where = [&](int column) {
    return source + ":" + std::to_string(line_no) + ":" + std::to_string(column) +
           (entry.name.empty() ? "" : " (entry '" + entry.name + "')");
  };
  auto finish = [&] {
    if (entry.maps.empty())
      throw InputError(source + ":" + std::to_string(entry.line) + ": entry '" + entry.name +
                       "' has no maps");
    try {
      systems.emplace_back(entry.name, ChannelLayout(entry.three_d ? "xyz" : "xy"), entry.maps,
                           entry.probabilities);
    } catch (const InputError& e) {
      throw InputError(source + ":" + std::to_string(entry.line) + " (entry '" + entry.name +
                       "'): " + e.what());
    }
    entry = Pending{};
    inside = false;
  };
  while (std::getline(lines, raw)) {
    ++line_no;
    std::string line = raw.substr(0, raw.find(';'));
    std::size_t pos = 0;
    while (pos < line.size()) {
      if (!inside) {
        const std::size_t brace = line.find('{', pos);
        if (brace == std::string::npos) {
          name_so_far += " " + line.substr(pos);
          break;
        }
        entry.name = trim(name_so_far + " " + line.substr(pos, brace - pos));
        name_so_far.clear();
        if (entry.name.empty()) throw InputError(where(int(brace) + 1) + ": an entry needs a name before '{'");
        std::string upper = entry.name;
        for (auto& ch : upper) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
        entry.three_d = upper.find("(3D)") != std::string::npos;
        entry.line = line_no;
        inside = true;
        pos = brace + 1;
        continue;
      }
      // Inside an entry: one row of numbers per line, maybe ended by '}'.
      const std::size_t close = line.find('}', pos);
      const std::string row = line.substr(pos, close == std::string::npos ? std::string::npos : close - pos);
      std::vector<double> numbers;
      std::size_t i = 0;
      while (i < row.size()) {
        const char ch = row[i];
        if (ch == ' ' || ch == '\t' || ch == ',' || ch == '\r') {
          ++i;
          continue;
        }
        const char* begin = row.c_str() + i;
        char* end = nullptr;
        const double v = std::strtod(begin, &end);
        if (end == begin)
          throw InputError(where(int(pos + i) + 1) + ": expected a number, found '" +
                           row.substr(i, row.find_first_of(" \t,", i) - i) + "'");
        numbers.push_back(v);
        i += static_cast<std::size_t>(end - begin);
      }
      if (!numbers.empty()) {
        const std::size_t expected = entry.three_d ? 13 : 7;
        if (numbers.size() != expected)
          throw InputError(where(int(pos) + 1) + ": a " + (entry.three_d ? "3D" : "2D") + " row needs " +
                           std::to_string(expected) + " numbers, found " + std::to_string(numbers.size()));
        const std::size_t map_index = entry.maps.size() + 1;
        for (double v : numbers)
          if (!std::isfinite(v))
            throw InputError(where(int(pos) + 1) + ": map " + std::to_string(map_index) +
                             " has a number that is NaN or infinite");
        for (double v : numbers)
          if (std::fabs(v) > kMaxCoefficient)
            throw InputError(where(int(pos) + 1) + ": map " + std::to_string(map_index) +
                             " has a number larger than 1e9 (iterating it would escape to infinity)");
        if (entry.three_d) {
          entry.maps.emplace_back(3, std::vector<double>(numbers.begin(), numbers.begin() + 9),
                                  std::vector<double>(numbers.begin() + 9, numbers.begin() + 12));
          entry.probabilities.push_back(numbers[12]);
        } else {
          const auto& n = numbers;
          entry.maps.emplace_back(2, std::vector<double>{n[0], n[1], n[2], n[3]}, std::vector<double>{n[4], n[5]});
          entry.probabilities.push_back(n[6]);
        }
      }
      if (close == std::string::npos) break;
      finish();
      pos = close + 1;
    }
  }
  if (inside) throw InputError(source + ":" + std::to_string(entry.line) + ": entry '" + entry.name + "' has no closing '}'");
  if (!trim(name_so_far).empty())
    throw InputError(source + ":" + std::to_string(line_no) + ": text after the last entry: '" + trim(name_so_far) + "'");
  if (systems.empty()) throw InputError(source + ": no entries found");
  return systems;
}

std::vector<Ifs> read_fractint(const std::string& path) { return parse_fractint(read_text_file(path), path); }

}  // namespace ifsforge
