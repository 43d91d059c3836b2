// compare_campaign_results DIR_A DIR_B: the trial result files of two campaign
// directories (DIR/trials/*.json) are the same set, and each pair is byte for byte the
// same apart from the timing keys (those ending in "_ms", one per line: see
// ResultStore). Exit 0 if so, 1 with the first difference of each file otherwise, 2 on
// a usage error.

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p)
{
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The result files of DIR/trials by name; temporary files (".name.tmp...") are skipped.
std::map<std::string, fs::path> resultFiles(const fs::path& dir)
{
  std::map<std::string, fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir / "trials")) {
    const std::string name = entry.path().filename().string();
    if (!name.empty() && name[0] != '.' && entry.path().extension() == ".json")
      files[name] = entry.path();
  }
  return files;
}

/// The lines of a result file without those of a timing key ("..._ms": value).
std::vector<std::string> linesWithoutTimings(const std::string& text)
{
  std::vector<std::string> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.find("_ms\": ") == std::string::npos)
      lines.push_back(line);
  return lines;
}

} // namespace

int main(int argc, char** argv)
{
  if (argc != 3) {
    std::cerr << "usage: compare_campaign_results DIR_A DIR_B\n";
    return 2;
  }
  const fs::path a = argv[1], b = argv[2];
  std::map<std::string, fs::path> files_a, files_b;
  try {
    files_a = resultFiles(a);
    files_b = resultFiles(b);
  } catch (const fs::filesystem_error& e) {
    std::cerr << "compare_campaign_results: " << e.what() << "\n";
    return 1;
  }
  int differences = 0;
  for (const auto& [name, path] : files_a)
    if (!files_b.count(name)) {
      std::cout << name << ": only in " << a.string() << "\n";
      ++differences;
    }
  for (const auto& [name, path] : files_b)
    if (!files_a.count(name)) {
      std::cout << name << ": only in " << b.string() << "\n";
      ++differences;
    }
  std::size_t compared = 0;
  for (const auto& [name, path_a] : files_a) {
    if (!files_b.count(name))
      continue;
    ++compared;
    const std::string text_a = slurp(path_a), text_b = slurp(files_b.at(name));
    // Both must be whole JSON documents: a truncated file would compare "equal" to
    // another truncated one.
    if (!nlohmann::json::accept(text_a) || !nlohmann::json::accept(text_b)) {
      std::cout << name << ": not valid JSON in one of the two directories\n";
      ++differences;
      continue;
    }
    const std::vector<std::string> la = linesWithoutTimings(text_a),
                                   lb = linesWithoutTimings(text_b);
    for (std::size_t i = 0; i < std::max(la.size(), lb.size()); ++i) {
      const std::string x = i < la.size() ? la[i] : "<end of file>";
      const std::string y = i < lb.size() ? lb[i] : "<end of file>";
      if (x != y) {
        std::cout << name << ": first difference (timing lines left out) at line "
                  << i + 1 << ":\n  " << a.string() << ": " << x << "\n  " << b.string()
                  << ": " << y << "\n";
        ++differences;
        break;
      }
    }
  }
  if (compared == 0 && differences == 0) {
    std::cout << "no trial results in " << a.string() << " nor " << b.string() << "\n";
    return 1;
  }
  if (differences) {
    std::cout << differences << " of " << files_a.size() << " trial results differ\n";
    return 1;
  }
  std::cout << compared << " trial results identical apart from the _ms timing keys\n";
  return 0;
}
