// MeshFilterInterface shim (the plugin API of MeshLab 2020.09: Debian 12's GUI and meshlabserver):
// a thin MeshFilterInterface over the shared filter description and the core. Everything it
// shows comes from filter_definition.h; everything it computes comes from sdp::parameterize.
#pragma once

#include <common/interfaces.h>
#include <QObject>

class FilterStraightestParamPlugin : public QObject, public MeshFilterInterface {
  Q_OBJECT
  MESHLAB_PLUGIN_IID_EXPORTER(MESH_FILTER_INTERFACE_IID)
  Q_INTERFACES(MeshFilterInterface)

 public:
  enum { FP_STRAIGHTEST_PARAM, FP_STRAIGHTEST_ATLAS };

  FilterStraightestParamPlugin();

  QString pluginName() const override;
  QString filterName(FilterIDType filter) const override;
  QString filterInfo(FilterIDType filter) const override;
  FilterClass getClass(QAction* action) override;
  int getPreConditions(QAction* action) const override;
  int postCondition(QAction* action) const override;
  FILTER_ARITY filterArity(QAction* action) const override;
  void initParameterSet(QAction* action, MeshModel& m, RichParameterList& parameters) override;
  bool applyFilter(QAction* action, MeshDocument& md, const RichParameterList& parameters,
                   vcg::CallBackPos* cb) override;

 private:
  void fail(const char* filter, const std::string& reason);
  void applyAtlas(const RichParameterList& parameters, MeshModel& mm, vcg::CallBackPos* cb);
};
