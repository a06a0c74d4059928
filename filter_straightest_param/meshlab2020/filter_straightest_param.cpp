#include "filter_straightest_param.h"

#include <exception>
#include <new>
#include <string>

#include "filter_straightest_param/filter_definition.h"
#include "filter_straightest_param/meshlab_filter.h"

FilterStraightestParamPlugin::FilterStraightestParamPlugin() {
  typeList << FP_STRAIGHTEST_PARAM;
  for (FilterIDType id : types()) actionList << new QAction(filterName(id), this);
}

QString FilterStraightestParamPlugin::pluginName() const {
  return "FilterStraightestParam";
}

QString FilterStraightestParamPlugin::filterName(FilterIDType) const {
  return QString::fromUtf8(sdp::filter::kFilterName);
}

QString FilterStraightestParamPlugin::filterInfo(FilterIDType) const {
  return QString::fromStdString(sdp::filter::filterHelp());
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

void FilterStraightestParamPlugin::initParameterSet(QAction*, MeshModel&,
                                                    RichParameterList& parameters) {
  sdp::meshlab::addFilterParameters<RichEnum, RichInt, RichBool, RichString>(parameters);
}

// meshlabserver prints only "Problem with filter" for a false return: the log line carries the
// reason to script users, errorMessage to the GUI's dialog.
void FilterStraightestParamPlugin::fail(const std::string& reason) {
  errorMessage = QString::fromStdString(reason);
  Log(GLLogStream::WARNING, "%s: %s", sdp::filter::kFilterName, reason.c_str());
}

bool FilterStraightestParamPlugin::applyFilter(QAction*, MeshDocument& md,
                                               const RichParameterList& parameters,
                                               vcg::CallBackPos* cb) {
  errorMessage.clear();
  try {
    MeshModel* mm = md.mm();
    if (mm == nullptr) throw sdp::ParameterizationError("no current mesh");

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
    fail(sdp::filter::currentFailureReason());
  }
  return false;
}

MESHLAB_PLUGIN_NAME_EXPORTER(FilterStraightestParamPlugin)
