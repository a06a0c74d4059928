// Qt-side helpers both MeshLab shims share: the filter description -> MeshLab parameters, the
// parameter values -> FilterValues, and the checkerboard texture file. MeshLab's parameter
// classes have the same names and constructors in 2020.09 and 2025.07 but are distinct types,
// so they come in as template arguments from each shim.
#pragma once

#include <QDir>
#include <QFileInfo>
#include <QImage>
#include <QString>
#include <QStringList>
#include <string>

#include "filter_straightest_param/checkerboard.h"
#include "filter_straightest_param/core/error.h"
#include "filter_straightest_param/filter_description.h"

namespace sdp::vcg_adapter {

inline QString qstr(const std::string& s) {
  return QString::fromStdString(s);
}

// Adds sdp::filter::parameters() to a MeshLab parameter list, in order, with docs/method.md §6
// labels.
template <class RichEnumT, class RichIntT, class RichBoolT, class RichStringT, class ParameterList>
void addFilterParameters(ParameterList& list) {
  using sdp::filter::ParameterType;
  for (const auto& p : sdp::filter::parameters()) {
    switch (p.type) {
      case ParameterType::Enum: {
        QStringList labels;
        for (const std::string& label : p.enum_labels) labels << qstr(label);
        list.addParam(RichEnumT(qstr(p.name), p.int_default, labels, qstr(p.label), qstr(p.help)));
        break;
      }
      case ParameterType::Int:
        list.addParam(RichIntT(qstr(p.name), p.int_default, qstr(p.label), qstr(p.help)));
        break;
      case ParameterType::Bool:
        list.addParam(RichBoolT(qstr(p.name), p.int_default != 0, qstr(p.label), qstr(p.help)));
        break;
      case ParameterType::String:
        list.addParam(
            RichStringT(qstr(p.name), qstr(p.string_default), qstr(p.label), qstr(p.help)));
        break;
    }
  }
}

// Reads the values back by the names of the shared description.
template <class ParameterList>
sdp::filter::FilterValues readFilterValues(const ParameterList& list) {
  sdp::filter::FilterValues v;
  for (const auto& p : sdp::filter::parameters()) {
    const QString name = qstr(p.name);
    if (p.name == "weights")
      v.weights = list.getEnum(name);
    else if (p.name == "boundary")
      v.boundary = list.getEnum(name);
    else if (p.name == "sourcevertex")
      v.source_vertex = list.getInt(name);
    else if (p.name == "stretchiterations")
      v.stretch_iterations = list.getInt(name);
    else if (p.name == "selectedonly")
      v.selected_only = list.getBool(name);
    else if (p.name == "texturename")
      v.texture_name = list.getString(name).toStdString();
    else if (p.name == "checkers")
      v.checkers = list.getInt(name);
    else if (p.name == "texturesize")
      v.texture_size = list.getInt(name);
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

// The texture name is checked before the (possibly long) run, so a typo fails at once; the
// size and checker ranges are toOptions()'s.
inline void checkTextureValues(const sdp::filter::FilterValues& values) {
  textureFileName(values.texture_name);
}

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

}  // namespace sdp::vcg_adapter
