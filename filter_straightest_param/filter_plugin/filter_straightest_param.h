// FilterPlugin shim (the plugin API of MeshLab 2022 and later: their GUIs and pymeshlab): a thin
// FilterPlugin over the shared filter descriptions and the core, with two filters. pymeshlab
// exposes them as MeshSet.compute_texcoord_parametrization_straightest_distances(...) and
// ..._straightest_distances_atlas(...), each returning its report dict.
#pragma once

#include <common/plugins/interfaces/filter_plugin.h>
#include <QObject>

class FilterStraightestParamPlugin : public QObject, public FilterPlugin {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(FILTER_PLUGIN_IID)
  Q_INTERFACES(FilterPlugin)

 public:
  enum { FP_STRAIGHTEST_PARAM, FP_STRAIGHTEST_ATLAS };

  FilterStraightestParamPlugin();

  QString pluginName() const override;
  QString vendor() const override;
  QString filterName(ActionIDType filter) const override;
  QString pythonFilterName(ActionIDType filter) const override;
  QString filterInfo(ActionIDType filter) const override;
  FilterClass getClass(const QAction* action) const override;
  int getPreConditions(const QAction* action) const override;
  int postCondition(const QAction* action) const override;
  FilterArity filterArity(const QAction* action) const override;
  RichParameterList initParameterList(const QAction* action, const MeshModel& m) override;
  std::map<std::string, QVariant> applyFilter(const QAction* action,
                                              const RichParameterList& parameters, MeshDocument& md,
                                              unsigned int& postConditionMask,
                                              vcg::CallBackPos* cb) override;

 private:
  std::map<std::string, QVariant> applyAtlas(const RichParameterList& parameters, MeshModel& mm,
                                             vcg::CallBackPos* cb);
};
