// pitvol-accuracy DIR --envelope: the envelope table of a sweep made by
// `pitvol-sim sweep` (docs/accuracy.md, "The envelope sweeps").
#ifndef PV_TOOLS_ENVELOPE_TABLE_H
#define PV_TOOLS_ENVELOPE_TABLE_H

namespace pv::tools {

// argv as pitvol-accuracy got it (argv[1] the sweep directory); returns the
// exit status.
int envelope_main(int argc, char **argv);

}  // namespace pv::tools

#endif
