// The filter's one definition: the parameter table every front end is built from, and the report
// table behind the JSON, the log lines and the pymeshlab dict.
#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/common/error.h"
#include "filter_straightest_param/filter_definition.h"

namespace {

using sdp::filter::ParameterDescription;
using sdp::filter::ParameterType;

const ParameterDescription& row(const std::string& name_or_flag) {
  for (const auto& p : sdp::filter::parameters())
    if (p.name == name_or_flag || p.cli_flag == name_or_flag) return p;
  throw std::runtime_error("no row " + name_or_flag);
}

TEST(FilterDefinition, MeshLabParametersKeepTheirPublicNamesAndOrder) {
  std::vector<std::string> names;
  for (const auto& p : sdp::filter::parameters())
    if (p.inMeshLab()) names.push_back(p.name);
  // Scripts saved by earlier versions name exactly these (meshlabserver 2020.09 aborts otherwise).
  EXPECT_EQ(names,
            (std::vector<std::string>{"weights", "boundary", "sourcevertex", "stretchiterations",
                                      "selectedonly", "texturename", "checkers", "texturesize"}));
  const auto& weights = row("weights").choices;
  ASSERT_EQ(weights.size(), 5u);
  EXPECT_EQ(weights[0].label, "Straightest distances (cutting planes)");
  EXPECT_EQ(weights[4].cli_name, "uniform");
  EXPECT_EQ(row("boundary").choices[1].label, "Circle");
}

TEST(FilterDefinition, EveryRowIsWellFormed) {
  std::set<std::string> names, flags;
  for (const auto& p : sdp::filter::parameters()) {
    EXPECT_TRUE(p.inMeshLab() || p.inCli()) << p.label;
    if (p.inMeshLab()) EXPECT_TRUE(names.insert(p.name).second) << p.name;
    if (p.inCli()) EXPECT_TRUE(flags.insert(p.cli_flag).second) << p.cli_flag;
    EXPECT_FALSE(p.label.empty());
    EXPECT_FALSE(p.help.empty()) << p.label;
    switch (p.type) {
      case ParameterType::Enum:
      case ParameterType::Int:
        EXPECT_NE(p.int_field, nullptr) << p.label;
        EXPECT_LE(p.min, p.default_int) << p.label;
        EXPECT_GE(p.max, p.default_int) << p.label;
        break;
      case ParameterType::Bool:
        EXPECT_NE(p.bool_field, nullptr) << p.label;
        EXPECT_TRUE(p.cli_value.empty()) << "a CLI switch takes no value: " << p.cli_flag;
        break;
      case ParameterType::String:
        EXPECT_NE(p.string_field, nullptr) << p.label;
        break;
    }
  }
}

TEST(FilterDefinition, DefaultsAreTheProductsDefaults) {
  const sdp::filter::FilterValues values = sdp::filter::defaultValues();
  EXPECT_EQ(values.stretch_iterations, sdp::kDefaultStretchIterations);
  EXPECT_EQ(values.source_vertex, -1);
  EXPECT_EQ(values.texture_name, "straightest_checker.png");
  EXPECT_EQ(values.texture_size, 1024);
  EXPECT_FALSE(values.selected_only);
  const sdp::Options options = sdp::filter::toOptions(values);
  const sdp::Options product = sdp::productDefaults();
  EXPECT_EQ(options.weights, product.weights);
  EXPECT_EQ(options.boundary, product.boundary);
  EXPECT_EQ(options.stretch_iterations, product.stretch_iterations);
  EXPECT_EQ(options.refine_work_factor, product.refine_work_factor);
  EXPECT_EQ(options.refine_min_work, product.refine_min_work);
  EXPECT_EQ(options.time_limit_seconds, 0);
  EXPECT_EQ(options.free_boundary, product.free_boundary);
  EXPECT_EQ(options.source_vertex, -1) << "the front end maps its own numbering";
}

TEST(FilterDefinition, RangesAreCheckedWithOneWording) {
  sdp::filter::FilterValues values = sdp::filter::defaultValues();
  values.stretch_iterations = 101;
  try {
    sdp::filter::toOptions(values);
    FAIL() << "101 stretch iterations must be refused";
  } catch (const sdp::ParameterizationError& e) {
    EXPECT_STREQ(e.what(), "stretchiterations must be between 0 and 100, got 101");
  }
  values = sdp::filter::defaultValues();
  values.weights = 5;
  EXPECT_THROW(sdp::filter::toOptions(values), sdp::ParameterizationError);
  try {
    sdp::filter::checkValue(row("--texture-size"), 8, "--texture-size");
    FAIL() << "8 pixels is below the range";
  } catch (const sdp::ParameterizationError& e) {
    EXPECT_STREQ(e.what(), "--texture-size must be between 16 and 8192, got 8");
  }
}

TEST(FilterDefinition, ReportTableFeedsJsonAndTheLogLine) {
  sdp::Report report;
  report.l2_stretch = 1.25;
  report.source_vertex = 7;
  report.seconds = 0.5;
  const std::string json = report.toJson();
  size_t last = 0;
  for (const sdp::ReportField& field : sdp::reportFields()) {
    const size_t at = json.find("\"" + std::string(field.key) + "\": ");
    ASSERT_NE(at, std::string::npos) << field.key;
    EXPECT_GT(at, last) << field.key << " out of table order";
    last = at;
  }
  std::set<std::string> summary;
  for (const sdp::ReportField& field : sdp::reportFields())
    if (field.summary) summary.insert(field.key);
  EXPECT_EQ(summary, (std::set<std::string>{"l2_stretch", "linf_stretch", "flipped_faces",
                                            "fallbacks", "source_vertex", "seconds"}));
  const auto lines = sdp::filter::reportLines(report, {"a remark"});
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[1],
            "L2 stretch 1.2500, Linf stretch 0.0000, flipped faces 0, fallbacks 0, source vertex "
            "7, seconds 0.500");
  EXPECT_EQ(lines[2], "a remark");
}

TEST(FilterDefinition, MarkdownTablesHaveARowPerEntry) {
  const std::string parameters = sdp::filter::markdownTable("parameters");
  for (const auto& p : sdp::filter::parameters()) {
    EXPECT_NE(parameters.find(p.help), std::string::npos) << p.label;
  }
  const std::string report = sdp::filter::markdownTable("report");
  for (const sdp::ReportField& field : sdp::reportFields())
    EXPECT_NE(report.find("`" + std::string(field.key) + "`"), std::string::npos) << field.key;
  EXPECT_THROW(sdp::filter::markdownTable("none"), sdp::ParameterizationError);
}

}  // namespace
