// A headless run of our filter inside MeshLab 2022.02 or 2025.07, which have no meshlabserver:
// the version's own plugin manager loads its own plugins (the mesh I/O among them) and ours, its
// own importer opens the mesh, the filter runs with its default parameters (or NAME=VALUE
// overrides), and its own OBJ exporter writes per-wedge texture coordinates. Compiled against
// that version's headers, linked to its libmeshlab-common.so, run inside its Debian root
// (tests/meshlab_roots/headless_case.py drives it).
//
// usage: meshlab_harness SYSTEM_PLUGIN_DIR OUR_PLUGIN.so IN.off OUT.obj [NAME=INT ...]
//   OUR_PLUGIN.so  "installed": ours is in SYSTEM_PLUGIN_DIR already (a Debian package);
//                  "absent": ours must not be loaded anywhere, and the mesh is only opened and
//                  saved (MeshLab still works after the package is removed)
// Prints "report KEY VALUE" lines (the filter's returned dict) and MeshLab's log as "log: ...".
// Exit status: 0 mapped and saved; 3 the filter refused with MLException and the mesh is exactly
// as before; 4 refused but the mesh changed; 1 anything else (plugin or mesh not loaded, ...).
#include <common/globals.h>
#include <common/ml_document/mesh_document.h>
#include <common/mlexception.h>
#include <common/plugins/plugin_manager.h>
#include <common/utilities/load_save.h>
#include <wrap/io_trimesh/io_mask.h>
#include <QApplication>
#include <QDir>
#include <QFileInfo>
#include <QLocale>
#include <clocale>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>

namespace {

const char* const kFilterName = "Parametrization: Straightest Distances";

// Everything the filter could change: positions, faces, wedge UVs, per-face quality, textures.
std::size_t meshFingerprint(const MeshModel& mm) {
  const CMeshO& m = mm.cm;
  std::size_t h = std::hash<int>()(m.VN()) * 31 + std::hash<int>()(m.FN());
  auto mix = [&h](double value) { h = h * 1000003u ^ std::hash<double>()(value); };
  for (const auto& v : m.vert) {
    if (v.IsD()) continue;
    for (int k = 0; k < 3; ++k) mix(v.cP()[k]);
  }
  const bool wedge = mm.hasDataMask(MeshModel::MM_WEDGTEXCOORD);
  const bool quality = mm.hasDataMask(MeshModel::MM_FACEQUALITY);
  mix(wedge);
  mix(quality);
  for (const auto& f : m.face) {
    if (f.IsD()) continue;
    for (int k = 0; k < 3; ++k) {
      mix(static_cast<double>(f.cV(k) - &m.vert[0]));
      if (wedge) {
        mix(f.cWT(k).U());
        mix(f.cWT(k).V());
      }
    }
    if (quality) mix(f.cQ());
  }
  for (const std::string& t : m.textures) h = h * 31 + std::hash<std::string>()(t);
  return h;
}

void printLog(MeshDocument& md) {
  QStringList lines;
  md.Log.print(lines);
  for (const QString& line : lines) std::cout << "log: " << line.toStdString() << "\n";
}

// The attributes MeshLab's export dialog ticks by default (SaveMeshAttributesDialog:
// shouldBeChecked): each bit the exporter suggests whose data the mesh holds, the Polygonal box
// (IOM_BITPOLYGONAL) among them for a mesh read from polygons. I/O bits (io_mask.h).
int exportDialogDefaults(const MeshModel& mm, int defaults) {
  namespace io = vcg::tri::io;
  // The dialog's boxes, in its order (the camera box needs a valid shot: not for these meshes).
  const int boxes[] = {
      io::Mask::IOM_VERTQUALITY,  io::Mask::IOM_VERTFLAGS,   io::Mask::IOM_VERTCOLOR,
      io::Mask::IOM_VERTTEXCOORD, io::Mask::IOM_VERTNORMAL,  io::Mask::IOM_VERTRADIUS,
      io::Mask::IOM_FACEQUALITY,  io::Mask::IOM_FACEFLAGS,   io::Mask::IOM_FACECOLOR,
      io::Mask::IOM_FACENORMAL,   io::Mask::IOM_WEDGCOLOR,   io::Mask::IOM_WEDGTEXCOORD,
      io::Mask::IOM_WEDGNORMAL,   io::Mask::IOM_BITPOLYGONAL};
  int mask = io::Mask::IOM_VERTCOORD | io::Mask::IOM_FACEINDEX;
  for (int bit : boxes)
    if ((defaults & bit) && mm.hasDataMask(MeshModel::io2mm(bit))) mask |= bit;
  return mask;
}

// Saves the current mesh with MeshLab's own OBJ exporter as its export dialog does by default
// (per-wedge UVs and textures when the mesh has them), or positions and faces only.
int saveObj(PluginManager& plugins, MeshDocument& md, const char* path, bool wedge_uvs) {
  MeshModel* mm = md.mm();
  const QString out = QFileInfo(QString::fromLocal8Bit(path)).absoluteFilePath();
  IOPlugin* exporter = plugins.outputMeshPlugin("obj");
  if (exporter == nullptr) {
    std::cout << "no OBJ exporter loaded\n";
    return 1;
  }
  exporter->setLog(&md.Log);
  int capability = 0, defaults = 0;
  exporter->exportMaskCapability("obj", capability, defaults);
  namespace io = vcg::tri::io;
  if (wedge_uvs && !(capability & io::Mask::IOM_WEDGTEXCOORD)) {
    std::cout << "the OBJ exporter cannot write wedge texture coordinates\n";
    return 1;
  }
  const int mask = wedge_uvs ? exportDialogDefaults(*mm, defaults)
                             : io::Mask::IOM_VERTCOORD | io::Mask::IOM_FACEINDEX;
  if (wedge_uvs && !(mask & io::Mask::IOM_WEDGTEXCOORD)) {
    std::cout << "the export dialog would not save the wedge texture coordinates\n";
    return 1;
  }
  if (mask & io::Mask::IOM_BITPOLYGONAL) std::cout << "saving polygons\n";
  try {
    exporter->save("obj", out, *mm, mask, exporter->initSaveParameter("obj", *mm), nullptr);
    // The .mtl names the texture; MeshLab keeps the image in memory until the mesh is saved.
    if (wedge_uvs) mm->saveTextures(QFileInfo(out).absolutePath(), -1, &md.Log, nullptr);
  } catch (const MLException& e) {
    std::cout << "saving failed: " << e.what() << "\n";
    return 1;
  }
  std::cout << "saved " << out.toStdString() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: %s SYSTEM_PLUGIN_DIR OUR_PLUGIN.so IN OUT.obj [NAME=INT ...]\n",
                 argv[0]);
    return 2;
  }
  if (qEnvironmentVariableIsEmpty("QT_QPA_PLATFORM")) qputenv("QT_QPA_PLATFORM", "offscreen");
  QApplication app(argc, argv);
  // As MeshLab's main(): QApplication takes the locale from the environment, the I/O wants "C".
  std::setlocale(LC_ALL, "C");
  QLocale::setDefault(QLocale::C);
  std::cout << "meshlab " << meshlab::meshlabVersion() << " "
            << (meshlab::builtWithDoublePrecision() ? "double" : "float") << "\n";

  const std::string our_plugin = argv[2];
  // The singleton: MeshLab's load/save helpers find the I/O plugins through it.
  PluginManager& plugins = meshlab::pluginManagerInstance();
  try {
    plugins.loadPlugins(QDir(QString::fromLocal8Bit(argv[1])));
    if (our_plugin != "installed" && our_plugin != "absent")
      plugins.loadPlugin(QFileInfo(QString::fromLocal8Bit(argv[2])).absoluteFilePath());
  } catch (const MLException& e) {
    std::cout << "plugin loading failed: " << e.what() << "\n";
    return 1;
  }

  MeshDocument md;
  try {
    meshlab::loadMeshWithStandardParameters(
        QFileInfo(QString::fromLocal8Bit(argv[3])).absoluteFilePath(), md);
  } catch (const MLException& e) {
    std::cout << "MeshLab could not open the mesh: " << e.what() << "\n";
    return 1;
  }
  MeshModel* mm = md.mm();
  QAction* action = plugins.filterAction(kFilterName);
  FilterPlugin* filter = action ? plugins.getFilterPluginFromAction(action) : nullptr;
  if (our_plugin == "absent") {
    if (filter != nullptr) {
      std::cout << "the filter is still loaded\n";
      return 1;
    }
    std::cout << "the filter is not loaded\n";
    const int saved = saveObj(plugins, md, argv[4], false);
    std::fflush(nullptr);
    std::_Exit(saved);
  }
  if (mm == nullptr || filter == nullptr) {
    std::cout << (mm == nullptr ? "no mesh" : "the filter is not loaded") << "\n";
    return 1;
  }
  filter->setLog(&md.Log);
  QStringList missing;
  if (!filter->isFilterApplicable(action, *mm, missing)) {
    std::cout << "filter not applicable: " << missing.join(", ").toStdString() << "\n";
    return 1;
  }
  // As MainWindow::executeFilter does before applying.
  mm->updateDataMask(filter->getRequirements(action));
  RichParameterList parameters = filter->initParameterList(action, md);
  for (int i = 5; i < argc; ++i) {
    const std::string assignment = argv[i];
    const std::size_t equals = assignment.find('=');
    if (equals == std::string::npos) {
      std::cout << "bad parameter " << assignment << " (want NAME=INT)\n";
      return 2;
    }
    const QString name = QString::fromStdString(assignment.substr(0, equals));
    if (!parameters.hasParameter(name)) {
      std::cout << "no parameter " << name.toStdString() << "\n";
      return 2;
    }
    parameters.setValue(name, IntValue(std::atoi(assignment.c_str() + equals + 1)));
  }

  const std::size_t before = meshFingerprint(*mm);
  unsigned int post_condition_mask = MeshModel::MM_UNKNOWN;
  try {
    const std::map<std::string, QVariant> report =
        filter->applyFilter(action, parameters, md, post_condition_mask, nullptr);
    for (const auto& entry : report)
      std::cout << "report " << entry.first << " " << entry.second.toString().toStdString() << "\n";
  } catch (const MLException& e) {
    printLog(md);
    const bool untouched = meshFingerprint(*mm) == before;
    std::cout << "refused: " << e.what() << "\n"
              << "mesh untouched: " << (untouched ? "yes" : "no") << "\n";
    return untouched ? 3 : 4;
  }
  printLog(md);

  const int saved = saveObj(plugins, md, argv[4], true);
  if (saved != 0) return saved;
  std::fflush(nullptr);
  // The static plugin manager would unload plugins after QApplication is gone: skip teardown.
  std::_Exit(0);
}
