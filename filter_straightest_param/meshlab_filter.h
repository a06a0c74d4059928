// What every MeshLab shim shares (MeshLab 2020's MeshFilterInterface, 2022+'s FilterPlugin):
// the parameter table -> MeshLab parameters and back, the checkerboard texture file, and the
// run on a MeshModel. MeshLab's parameter classes and MeshModel have the same names and members
// in every version but are distinct types, so they come in as template arguments from each shim.
#pragma once

#include <QDir>
#include <QFileInfo>
#include <QImage>
#include <QString>
#include <QStringList>
#include <string>
#include <type_traits>

#include "core/common/error.h"
#include "filter_straightest_param/filter_definition.h"
#include "io/checkerboard.h"
#include "vcg_adapters/mesh_run.h"
#include "vcg_adapters/patch_adapter.h"

namespace sdp::meshlab {

inline QString qstr(const std::string& s) {
  return QString::fromStdString(s);
}

// The filters of the plugin: the patch filter and the atlas filter, each with its own table.
enum class Filter { Patch, Atlas };

// The filter behind a shim's action id: both shims number them FP_STRAIGHTEST_PARAM,
// FP_STRAIGHTEST_ATLAS.
template <class Plugin>
Filter filterOf(int id) {
  return id == Plugin::FP_STRAIGHTEST_ATLAS ? Filter::Atlas : Filter::Patch;
}

inline const std::vector<sdp::filter::ParameterDescription>& tableOf(Filter filter) {
  return filter == Filter::Atlas ? sdp::filter::atlasParameters() : sdp::filter::parameters();
}
inline const char* nameOf(Filter filter) {
  return filter == Filter::Atlas ? sdp::filter::kAtlasFilterName : sdp::filter::kFilterName;
}
inline const char* pythonNameOf(Filter filter) {
  return filter == Filter::Atlas ? sdp::filter::kAtlasPythonFilterName
                                 : sdp::filter::kPythonFilterName;
}
inline std::string helpOf(Filter filter) {
  return filter == Filter::Atlas ? sdp::filter::atlasHelp() : sdp::filter::filterHelp();
}

// Adds the MeshLab rows of the filter's table to a MeshLab parameter list, in order, with
// docs/method.md §6 labels.
template <class RichEnumT, class RichIntT, class RichBoolT, class RichStringT, class ParameterList>
void addFilterParameters(ParameterList& list, Filter filter = Filter::Patch) {
  using sdp::filter::ParameterType;
  for (const auto& p : tableOf(filter)) {
    if (!p.inMeshLab()) continue;
    switch (p.type) {
      case ParameterType::Enum: {
        QStringList labels;
        for (const auto& choice : p.choices) labels << qstr(choice.label);
        list.addParam(RichEnumT(qstr(p.name), p.default_int, labels, qstr(p.label), qstr(p.help)));
        break;
      }
      case ParameterType::Int:
        list.addParam(RichIntT(qstr(p.name), p.default_int, qstr(p.label), qstr(p.help)));
        break;
      case ParameterType::Bool:
        list.addParam(RichBoolT(qstr(p.name), p.default_int != 0, qstr(p.label), qstr(p.help)));
        break;
      case ParameterType::String:
        list.addParam(
            RichStringT(qstr(p.name), qstr(p.default_string), qstr(p.label), qstr(p.help)));
        break;
    }
  }
}

// Reads the values back by the table's names; the CLI-only rows keep their defaults.
template <class ParameterList>
sdp::filter::FilterValues readFilterValues(const ParameterList& list,
                                           Filter filter = Filter::Patch) {
  using sdp::filter::ParameterType;
  sdp::filter::FilterValues v =
      filter == Filter::Atlas ? sdp::filter::atlasDefaultValues() : sdp::filter::defaultValues();
  for (const auto& p : tableOf(filter)) {
    if (!p.inMeshLab()) continue;
    const QString name = qstr(p.name);
    switch (p.type) {
      case ParameterType::Enum:
        v.*p.int_field = list.getEnum(name);
        break;
      case ParameterType::Int:
        v.*p.int_field = list.getInt(name);
        break;
      case ParameterType::Bool:
        v.*p.bool_field = list.getBool(name);
        break;
      case ParameterType::String:
        v.*p.string_field = list.getString(name).toStdString();
        break;
    }
  }
  return v;
}

// A file name for the texture: no folders (it is written next to the mesh), an image suffix
// Qt can write (".png" added otherwise).
inline QString textureFileName(const std::string& texture_name) {
  QString name = qstr(texture_name).trimmed();
  if (name.isEmpty()) throw sdp::ParameterizationError("texturename is empty");
  if (name.contains('/') || name.contains('\\')) {
    throw sdp::ParameterizationError("texturename must be a file name without folders: " +
                                     texture_name);
  }
  const QString suffix = QFileInfo(name).suffix().toLower();
  if (suffix != "png" && suffix != "jpg" && suffix != "jpeg" && suffix != "bmp") name += ".png";
  return name;
}

struct CheckerTexture {
  QString name;  // file name, e.g. "straightest_checker.png"
  QString path;  // absolute path of the written file
  QImage image;
};

inline QImage checkerImage(int size, int checkers) {
  const std::vector<unsigned char> rgb = sdp::checkerboardRGB(size, checkers);
  // copy(): the QImage must own its pixels once `rgb` is gone.
  return QImage(rgb.data(), size, size, size * 3, QImage::Format_RGB888)
      .copy()
      .convertToFormat(QImage::Format_RGB32);
}

// Writes the checkerboard next to the mesh file; into the temporary folder when the mesh has no
// file yet or its folder is not writable.
inline CheckerTexture writeCheckerTexture(const QString& mesh_file, const std::string& texture_name,
                                          int size, int checkers) {
  CheckerTexture t;
  t.name = textureFileName(texture_name);
  t.image = checkerImage(size, checkers);
  if (t.image.isNull()) throw sdp::ParameterizationError("not enough memory for the texture");
  QStringList folders;
  if (!mesh_file.isEmpty()) folders << QFileInfo(mesh_file).absolutePath();
  folders << QDir::tempPath();
  for (const QString& folder : folders) {
    const QString path = QDir(folder).absoluteFilePath(t.name);
    if (t.image.save(path)) {
      t.path = path;
      return t;
    }
  }
  throw sdp::ParameterizationError("cannot write the texture " + t.name.toStdString());
}

// MeshLab's progress callback (vcg::CallBackPos, may be null) as the core's, each stage worded
// prefix + stage + suffix. MeshLab's callbacks cannot cancel reliably (meshlabserver's always
// says "go on"), so the run is never cancelled from here.
template <class CallBackPos>
sdp::ProgressCallback progressTo(CallBackPos* cb, std::string prefix, std::string suffix) {
  if (cb == nullptr) return {};
  return [cb, prefix, suffix](const char* stage, int percent) {
    cb(percent, (prefix + stage + suffix).c_str());
    return true;
  };
}

// MeshLab's progress callback as the atlas's stage bar (AtlasOptions::stage_progress): MeshLab
// redraws only when the bar's position moves, and at millions of faces the run's percentage
// moves every few seconds; the text names the stage and the run's percentage.
template <class CallBackPos>
sdp::atlas::StageProgressCallback stageProgressTo(CallBackPos* cb, std::string prefix,
                                                  std::string suffix) {
  if (cb == nullptr) return {};
  return [cb, prefix, suffix](const char* stage, int stage_percent, int run_percent) {
    const std::string text =
        prefix + stage + " (" + std::to_string(run_percent) + "% of the atlas)" + suffix;
    cb(stage_percent, text.c_str());
  };
}

struct MeshModelRun {
  vcg_adapter::MeshRun run;            // its report describes the UVs as the mesh now holds them
  CheckerTexture texture;              // written, not yet attached
  bool polygons_as_triangles = false;  // keepTrianglesThatCarryTheMap turned polygons off
};

// The note a polygon mesh gets once its triangles carry the map.
constexpr const char* kPolygonalNote =
    "the mesh's polygons are saved as the triangles that carry the map: MeshLab's polygonal "
    "export (the export dialog's Polygonal box, pymeshlab's save_polygonal) drops per-wedge "
    "texture coordinates, so it is turned off for this mesh";

// MeshLab keeps a polygon mesh as triangles with faux edges and the MM_POLYGONAL flag; its
// exporters then rebuild the polygons (PolygonSupport::ImportFromTriMesh), which keeps no
// per-wedge texture coordinates, and every save with default options (the export dialog,
// pymeshlab's save_current_mesh) would lose the map. Clearing the flag makes every front end
// save the triangles with their UVs. True when the mesh was polygonal (kPolygonalNote applies).
template <class MeshModelT>
bool keepTrianglesThatCarryTheMap(MeshModelT& mm) {
  if (!mm.hasDataMask(MeshModelT::MM_POLYGONAL)) return false;
  mm.clearDataMask(MeshModelT::MM_POLYGONAL);
  return true;
}

// The part of applyFilter every shim shares, in the order that keeps a failure from touching the
// mesh: read and check the parameters, run the core, prepare what will be stored, write the
// checkerboard file, and only then change the mesh. Attaching the texture, logging and the
// return value differ and stay in the shims.
template <class MeshModelT, class ParameterList>
MeshModelRun parameterizeMeshModel(MeshModelT& mm, const ParameterList& parameters,
                                   const sdp::ProgressCallback& progress) {
  using Mesh = std::decay_t<decltype(mm.cm)>;
  const sdp::filter::FilterValues values = readFilterValues(parameters);
  textureFileName(values.texture_name);  // a typo fails at once, not after a long run
  sdp::Options options = sdp::filter::toOptions(values);
  vcg_adapter::setMeshLabStorage(options);
  options.progress = progress;
  MeshModelRun out{
      vcg_adapter::runOnMesh(mm.cm, options, values.selected_only, values.source_vertex), {}};

  vcg_adapter::WriteOptions write;
  // Per-vertex UVs only where the mesh already had them, so they do not go stale.
  write.vertex_texcoords = mm.hasDataMask(MeshModelT::MM_VERTTEXCOORD);
  const auto stored = vcg_adapter::prepareLayout<Mesh>(out.run.input, out.run.result.layout,
                                                       out.run.result.face_stretch);
  // The texture is written before the mesh changes, so its failure too leaves the mesh as it was.
  out.texture =
      writeCheckerTexture(mm.fullName(), values.texture_name, values.texture_size, values.checkers);

  mm.updateDataMask(MeshModelT::MM_WEDGTEXCOORD | MeshModelT::MM_FACEQUALITY);
  vcg_adapter::applyResult(mm.cm, out.run.input, stored, write);
  out.polygons_as_triangles = keepTrianglesThatCarryTheMap(mm);
  if (out.polygons_as_triangles) out.run.notes.push_back(kPolygonalNote);
  return out;
}

// The report's log lines: the filter's wording plus this run's remarks.
inline std::vector<std::string> logLines(const MeshModelRun& done) {
  return sdp::filter::reportLines(done.run.result.report, done.run.notes);
}

struct MeshModelAtlas {
  vcg_adapter::AtlasRun run;
  CheckerTexture texture;  // written, not yet attached
  bool polygons_as_triangles = false;
  std::vector<std::string> notes;  // the front end's remarks (kPolygonalNote)
};

// The atlas filter's applyFilter part every shim shares, in the same failure-safe order as the
// patch filter's: parameters, the core, the stored values, the texture file, then the mesh
// (wedge UVs, per-face quality and the per-face attribute `chart` only).
template <class MeshModelT, class ParameterList>
MeshModelAtlas atlasMeshModel(MeshModelT& mm, const ParameterList& parameters,
                              const sdp::atlas::StageProgressCallback& progress) {
  using Mesh = std::decay_t<decltype(mm.cm)>;
  const sdp::filter::FilterValues values = readFilterValues(parameters, Filter::Atlas);
  textureFileName(values.texture_name);
  sdp::atlas::AtlasOptions options = sdp::filter::toAtlasOptions(values);
  options.storage = sdp::UVStorage::FloatAndSixDecimals;
  options.stage_progress = progress;
  MeshModelAtlas out{vcg_adapter::atlasOnMesh(mm.cm, options, values.selected_only), {}};
  const auto stored = vcg_adapter::prepareLayout<Mesh>(out.run.input, out.run.result.layout,
                                                       out.run.result.face_stretch);
  out.texture =
      writeCheckerTexture(mm.fullName(), values.texture_name, values.texture_size, values.checkers);
  mm.updateDataMask(MeshModelT::MM_WEDGTEXCOORD | MeshModelT::MM_FACEQUALITY);
  vcg_adapter::WriteOptions write;  // wedges only: a seam vertex has no single coordinate
  vcg_adapter::applyResult(mm.cm, out.run.input, stored, write);
  vcg_adapter::applyCharts(mm.cm, out.run.input, out.run.result.layout.chart);
  out.polygons_as_triangles = keepTrianglesThatCarryTheMap(mm);
  if (out.polygons_as_triangles) out.notes.push_back(kPolygonalNote);
  return out;
}

}  // namespace sdp::meshlab
