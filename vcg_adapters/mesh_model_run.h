// The part of applyFilter both MeshLab shims share, in the order that keeps a failure from
// touching the mesh: read and check the parameters, run the core, prepare what will be stored,
// write the checkerboard file, and only then change the mesh. MeshModelT is either MeshLab's
// MeshModel (2020.09 and 2025.07 name these members alike); attaching the texture, logging and
// the return value differ and stay in the shims.
#pragma once

#include <type_traits>

#include "vcg_adapters/filter_run.h"
#include "vcg_adapters/meshlab_support.h"
#include "vcg_adapters/patch_adapter.h"

namespace sdp::vcg_adapter {

struct MeshModelRun {
  FilterRun run;
  sdp::UVMeasures stored_metrics;  // of the UVs as the mesh now holds them
  CheckerTexture texture;          // written, not yet attached
};

template <class MeshModelT, class ParameterList>
MeshModelRun parameterizeMeshModel(MeshModelT& mm, const ParameterList& parameters,
                                   const ProgressSink& progress) {
  using Mesh = std::decay_t<decltype(mm.cm)>;
  const sdp::filter::FilterValues values = readFilterValues(parameters);
  checkTextureValues(values);
  MeshModelRun out{runParameterization(mm.cm, values, progress), {}, {}};

  WriteOptions write;
  // Per-vertex UVs only where the mesh already had them, so they do not go stale.
  write.vertex_texcoords = mm.hasDataMask(MeshModelT::MM_VERTTEXCOORD);
  const auto stored = prepareResult<Mesh>(out.run.input, out.run.result);
  // Nothing below runs unless the core succeeded; the texture is written before the mesh
  // changes, so its failure too leaves the mesh as it was.
  out.texture =
      writeCheckerTexture(mm.fullName(), values.texture_name, values.texture_size, values.checkers);

  mm.updateDataMask(MeshModelT::MM_WEDGTEXCOORD | MeshModelT::MM_FACEQUALITY);
  applyResult(mm.cm, out.run.input, stored, write);
  out.stored_metrics = stored.metrics;
  return out;
}

}  // namespace sdp::vcg_adapter
