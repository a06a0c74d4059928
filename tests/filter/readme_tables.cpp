// Checks or rewrites the docs/usage.md blocks generated from the filter's definition:
//   <!-- table:parameters --> ... <!-- /table:parameters -->
//   <!-- table:report --> ... <!-- /table:report -->
//   <!-- table:atlas-parameters --> ... and <!-- table:atlas-report --> ...
// Usage: readme_tables docs/usage.md --check|--write. Exit 1 (with the reason) when --check finds a
// block missing or different.
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "filter_straightest_param/filter_definition.h"

int main(int argc, char** argv) {
  if (argc != 3 || (std::string(argv[2]) != "--check" && std::string(argv[2]) != "--write")) {
    std::cerr << "usage: readme_tables docs/usage.md --check|--write\n";
    return 2;
  }
  const std::string path = argv[1];
  const bool write = std::string(argv[2]) == "--write";
  std::ifstream in(path);
  if (!in) {
    std::cerr << "readme_tables: cannot read " << path << "\n";
    return 1;
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  int problems = 0;
  for (const std::string name : {"parameters", "report", "atlas-parameters", "atlas-report"}) {
    const std::string begin = "<!-- table:" + name + " -->\n";
    const std::string end = "<!-- /table:" + name + " -->";
    const size_t a = text.find(begin);
    const size_t b = a == std::string::npos ? a : text.find(end, a);
    if (b == std::string::npos) {
      std::cerr << "readme_tables: " << path << " has no " << begin.substr(0, begin.size() - 1)
                << " ... " << end << " block\n";
      ++problems;
      continue;
    }
    const std::string generated = sdp::filter::markdownTable(name);
    const size_t body = a + begin.size();
    if (text.compare(body, b - body, generated) == 0) continue;
    if (write) {
      text.replace(body, b - body, generated);
    } else {
      std::cerr << "readme_tables: the " << name << " table in " << path
                << " differs from the filter's definition; run scripts/update-readme-tables.sh\n";
      ++problems;
    }
  }
  if (write && problems == 0) std::ofstream(path) << text;
  return problems == 0 ? 0 : 1;
}
