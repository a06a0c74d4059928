#include "filter_straightest_param.h"

#include <common/mlexception.h>
#include <exception>
#include <new>
#include <string>

#include "filter_straightest_param/filter_definition.h"
#include "filter_straightest_param/meshlab_filter.h"

FilterStraightestParamPlugin::FilterStraightestParamPlugin() {
  typeList = {FP_STRAIGHTEST_PARAM, FP_STRAIGHTEST_ATLAS};
  for (ActionIDType id : types()) actionList.push_back(new QAction(filterName(id), this));
}

QString FilterStraightestParamPlugin::pluginName() const {
  return "FilterStraightestParam";
}

QString FilterStraightestParamPlugin::vendor() const {
  return "straightest_param";
}

constexpr auto filterOf = &sdp::meshlab::filterOf<FilterStraightestParamPlugin>;

QString FilterStraightestParamPlugin::filterName(ActionIDType id) const {
  return QString::fromUtf8(sdp::meshlab::nameOf(filterOf(id)));
}

// Set explicitly (docs/method.md §6), not derived from the menu name as FilterPlugin's default
// does.
QString FilterStraightestParamPlugin::pythonFilterName(ActionIDType id) const {
  return QString::fromUtf8(sdp::meshlab::pythonNameOf(filterOf(id)));
}

QString FilterStraightestParamPlugin::filterInfo(ActionIDType id) const {
  return QString::fromStdString(sdp::meshlab::helpOf(filterOf(id)));
}

FilterPlugin::FilterClass FilterStraightestParamPlugin::getClass(const QAction*) const {
  return FilterPlugin::Texture;
}

int FilterStraightestParamPlugin::getPreConditions(const QAction*) const {
  return MeshModel::MM_FACENUMBER;
}

int FilterStraightestParamPlugin::postCondition(const QAction*) const {
  return MeshModel::MM_WEDGTEXCOORD | MeshModel::MM_VERTTEXCOORD | MeshModel::MM_FACEQUALITY;
}

FilterPlugin::FilterArity FilterStraightestParamPlugin::filterArity(const QAction*) const {
  return SINGLE_MESH;
}

RichParameterList FilterStraightestParamPlugin::initParameterList(const QAction* action,
                                                                  const MeshModel&) {
  RichParameterList parameters;
  sdp::meshlab::addFilterParameters<RichEnum, RichInt, RichBool, RichString>(parameters,
                                                                             filterOf(ID(action)));
  return parameters;
}

// The atlas: the texture attached as for the patch filter, the atlas report's log lines and
// summary dict.
std::map<std::string, QVariant> FilterStraightestParamPlugin::applyAtlas(
    const RichParameterList& parameters, MeshModel& mm, vcg::CallBackPos* cb) {
  const auto progress = sdp::meshlab::stageProgressTo(cb, "straightest distances atlas: ", "");
  const auto done = sdp::meshlab::atlasMeshModel(mm, parameters, progress);
  mm.clearTextures();
  mm.addTexture(done.texture.name.toStdString(), done.texture.image);
  for (const std::string& line : done.notes) log("%s", line.c_str());
  for (const std::string& line : sdp::filter::atlasReportLines(done.run.result.report))
    log("%s", line.c_str());
  log("texture %s", qUtf8Printable(done.texture.path));
  if (cb != nullptr) cb(100, "done");
  std::map<std::string, QVariant> values;
  for (const auto& field : sdp::atlas::atlasSummaryFields()) {
    const double value = field.number(done.run.result.report);
    values[field.key] = field.integer ? QVariant(static_cast<int>(value)) : QVariant(value);
  }
  // pymeshlab hands only numbers on to Python (a string is dropped from the dict): the notes
  // are counts here, worded by the pip package (pymeshlab_straightest adds `notes`).
  values["polygons_as_triangles"] = QVariant(done.polygons_as_triangles);
  return values;
}

std::map<std::string, QVariant> FilterStraightestParamPlugin::applyFilter(
    const QAction* action, const RichParameterList& parameters, MeshDocument& md,
    unsigned int& /*postConditionMask*/, vcg::CallBackPos* cb) {
  // Every failure leaves here as MLException with the core's one-line reason: pymeshlab turns it
  // into PyMeshLabException, the GUI into its error dialog. Nothing else may escape.
  std::string reason;
  const sdp::meshlab::Filter which = filterOf(ID(action));
  try {
    MeshModel* mm = md.mm();
    if (mm == nullptr) throw sdp::ParameterizationError("no current mesh");
    if (which == sdp::meshlab::Filter::Atlas) return applyAtlas(parameters, *mm, cb);

    const auto progress = sdp::meshlab::progressTo(cb, "", "");
    const auto done = sdp::meshlab::parameterizeMeshModel(*mm, parameters, progress);

    // 2025.07 keeps the image in memory under its file name; saving the mesh writes it beside
    // the saved file, and the GUI shows it from memory.
    mm->clearTextures();
    mm->addTexture(done.texture.name.toStdString(), done.texture.image);

    for (const std::string& line : sdp::meshlab::logLines(done)) log("%s", line.c_str());
    log("texture %s", qUtf8Printable(done.texture.path));
    if (cb != nullptr) cb(100, "done");

    // The pymeshlab dict: the report's summary fields (docs/method.md §6).
    std::map<std::string, QVariant> values;
    const sdp::Report& report = done.run.result.report;
    for (const sdp::ReportField& field : sdp::reportFields()) {
      if (!field.summary) continue;
      const double value = field.number(report);
      values[field.key] = field.integer ? QVariant(static_cast<int>(value)) : QVariant(value);
    }
    values["polygons_as_triangles"] = QVariant(done.polygons_as_triangles);
    return values;
  } catch (const MLException&) {
    throw;
  } catch (...) {
    reason = sdp::filter::currentFailureReason();
  }
  log(GLLogStream::WARNING, "%s: %s", sdp::meshlab::nameOf(which), reason.c_str());
  throw MLException(QString::fromStdString(reason));
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterStraightestParamPlugin)
