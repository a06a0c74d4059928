#include "filter_straightest_param.h"

#include <exception>
#include <new>
#include <string>

#include "filter_straightest_param/filter_definition.h"
#include "filter_straightest_param/meshlab_filter.h"

FilterStraightestParamPlugin::FilterStraightestParamPlugin() {
  typeList << FP_STRAIGHTEST_PARAM << FP_STRAIGHTEST_ATLAS;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString FilterStraightestParamPlugin::pluginName() const {
  return "FilterStraightestParam";
}

constexpr auto filterOf = &sdp::meshlab::filterOf<FilterStraightestParamPlugin>;

QString FilterStraightestParamPlugin::filterName(FilterIDType id) const {
  return QString::fromUtf8(sdp::meshlab::nameOf(filterOf(id)));
}

QString FilterStraightestParamPlugin::filterInfo(FilterIDType id) const {
  return QString::fromStdString(sdp::meshlab::helpOf(filterOf(id)));
}

MeshFilterInterface::FilterClass FilterStraightestParamPlugin::getClass(QAction*) {
  // Texture also makes the GUI reload cm.textures after the run (MainWindow::updateTexture).
  return MeshFilterInterface::Texture;
}

int FilterStraightestParamPlugin::getPreConditions(QAction*) const {
  return MeshModel::MM_FACENUMBER;
}

int FilterStraightestParamPlugin::postCondition(QAction*) const {
  return MeshModel::MM_WEDGTEXCOORD | MeshModel::MM_VERTTEXCOORD | MeshModel::MM_FACEQUALITY;
}

MeshFilterInterface::FILTER_ARITY FilterStraightestParamPlugin::filterArity(QAction*) const {
  return SINGLE_MESH;
}

void FilterStraightestParamPlugin::initParameterSet(QAction* action, MeshModel&,
                                                    RichParameterList& parameters) {
  sdp::meshlab::addFilterParameters<RichEnum, RichInt, RichBool, RichString>(parameters,
                                                                             filterOf(ID(action)));
}

// meshlabserver prints only "Problem with filter" for a false return: the log line carries the
// reason to script users, errorMessage to the GUI's dialog.
void FilterStraightestParamPlugin::fail(const char* filter, const std::string& reason) {
  errorMessage = QString::fromStdString(reason);
  Log(GLLogStream::WARNING, "%s: %s", filter, reason.c_str());
}

// The atlas: the texture attached by absolute path as for the patch filter, the atlas report's
// log lines.
void FilterStraightestParamPlugin::applyAtlas(const RichParameterList& parameters, MeshModel& mm,
                                              vcg::CallBackPos* cb) {
  const auto progress = sdp::meshlab::stageProgressTo(cb, "straightest distances atlas: ", "\n");
  const auto done = sdp::meshlab::atlasMeshModel(mm, parameters, progress);
  mm.cm.textures.clear();
  mm.cm.textures.push_back(done.texture.path.toStdString());
  for (const std::string& line : done.notes) Log("%s", line.c_str());
  for (const std::string& line : sdp::filter::atlasReportLines(done.run.result.report))
    Log("%s", line.c_str());
  Log("texture %s", qUtf8Printable(done.texture.path));
  if (cb != nullptr) cb(100, "straightest distances atlas: done\n");
}

bool FilterStraightestParamPlugin::applyFilter(QAction* action, MeshDocument& md,
                                               const RichParameterList& parameters,
                                               vcg::CallBackPos* cb) {
  errorMessage.clear();
  const sdp::meshlab::Filter which = filterOf(ID(action));
  try {
    MeshModel* mm = md.mm();
    if (mm == nullptr) throw sdp::ParameterizationError("no current mesh");
    if (which == sdp::meshlab::Filter::Atlas) {
      applyAtlas(parameters, *mm, cb);
      return true;
    }

    // meshlabserver prints the text as is: one line per stage.
    const auto progress = sdp::meshlab::progressTo(cb, "straightest distances: ", "\n");
    const auto done = sdp::meshlab::parameterizeMeshModel(*mm, parameters, progress);

    // 2020.09 loads cm.textures relative to the process's current folder (not the mesh's), so
    // the absolute path is what lets the GUI show the checkerboard at once; the OBJ exporter
    // writes it to map_Kd as is.
    mm->cm.textures.clear();
    mm->cm.textures.push_back(done.texture.path.toStdString());

    for (const std::string& line : sdp::meshlab::logLines(done)) Log("%s", line.c_str());
    Log("texture %s", qUtf8Printable(done.texture.path));
    if (cb != nullptr) cb(100, "straightest distances: done\n");
    return true;
  } catch (...) {
    fail(sdp::meshlab::nameOf(which), sdp::filter::currentFailureReason());
  }
  return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterStraightestParamPlugin)
