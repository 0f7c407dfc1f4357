// `pitvol measure FILE --export-levelled OUT.ply`: the scan's points in the
// core's levelled frame (bottom plane at z = 0, the pit opening towards +z),
// with the rim height the core measured, for measuring the same cloud with
// other programs (host_tools/peers: the 2.5D grid, CloudCompare, Poisson).
#ifndef PV_TOOLS_EXPORT_LEVELLED_H
#define PV_TOOLS_EXPORT_LEVELLED_H

#include <cstdint>
#include <string>

#include "measure.h"
#include "pitvol/pitvol.h"

namespace pv::tools {

// Points the export writes: finite and within a kilometre, as the core
// accepts them. run_measure() counts them while it streams the file.
bool exportable(const pv_point_t &p);

// Reads opt.path again (memory stays bounded) and writes binary little
// endian PLY (float x, y, z) to out_path, with header comments
//   comment pitvol_rim_mm <rim height, levelled mm, -1 if none>
//   comment pitvol_rim_from_ground <1|0>
//   comment pitvol_transform <r00 .. r22 t0 t1 t2>  (levelled = R raw + t)
// count: exportable points in the file. false with *err on failure.
bool export_levelled(const MeasureOptions &opt, pv_session_t *session, uint64_t count,
                     const std::string &out_path, std::string *err);

}  // namespace pv::tools

#endif
