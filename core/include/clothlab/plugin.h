/*
 * ClothLab plugin ABI — the only contract between the host and a plugin library. This header
 * includes the whole ABI, one concept per header in clothlab/abi/: version.h (the version and
 * the compatibility rule), status.h (errors), params.h (parameter schemas), system.h (the cloth
 * as an integrator sees it), integrator.h, scenario.h and entry.h (the one exported symbol).
 * The history of the minors is in clothlab/abi/CHANGELOG.md; the reference with the extension
 * table is docs/reference/abi.md.
 *
 * Plain C (C99 and C++ compatible). Only C types cross the boundary: fixed-width
 * integers, double, pointers to arrays and `const char*`. Rules:
 *  - A library exports exactly one symbol, `clothlab_plugin_entry`, returning a
 *    descriptor whose first field is the ABI version it was built against. The host
 *    checks that version before reading anything else with clothlab_abi_is_compatible():
 *    a different major is refused, any minor of the same major is accepted.
 *  - Every struct carries `struct_size`; readers must not touch fields beyond it, and
 *    accept any size from the smallest published one (CLOTHLAB_*_SIZE_1_0) up. The structs
 *    are frozen: the ABI grows by extensions, optional interfaces looked up by a versioned
 *    string id ("clothlab.jacobian/1") through `get_extension` on both sides, NULL when
 *    absent. A new capability is a new id, a change of one is a new revision ("/2"); a
 *    published extension struct is never edited. One header per extension, in clothlab/ext/:
 *    host side (tools/reference.py checks these lists against clothlab/ext/):
 *      clothlab.attachment-targets/1, clothlab.cg-step/1, clothlab.contacts/1,
 *      clothlab.definite-jacobian/1, clothlab.definite-jacobian/2, clothlab.external-forces/1,
 *      clothlab.external-forces/2, clothlab.grid/1, clothlab.jacobian/1, clothlab.reductions/1,
 *      clothlab.threads/1, clothlab.topology/1;
 *    integrator side:
 *      clothlab.explicit-scheme/1, clothlab.integrator-traits/1, clothlab.solver-statistics/1;
 *    scenario side:
 *      clothlab.air/1, clothlab.attachments/1, clothlab.colliders/1, clothlab.colliders/2,
 *      clothlab.mesh/1;
 *    plugin side (an integrator's or a scenario's):
 *      clothlab.text-parameters/1.
 *  - Errors are status codes plus a message written into a caller-owned buffer.
 *    No exception, longjmp or C++ type ever crosses the boundary.
 *  - Ownership: the host owns the cloth state and every vector of a clothlab_system;
 *    a plugin owns the instances it creates and frees them in `destroy`. Strings in
 *    descriptors and parameter specs are static: valid while the library is loaded.
 *  - Threads: every function is called from one host thread at a time per instance.
 *    Different instances may be used concurrently from different threads.
 */
#ifndef CLOTHLAB_PLUGIN_H
#define CLOTHLAB_PLUGIN_H

/* In the order a reader meets the concepts; each header includes what it needs. */
/* clang-format off */
#include <clothlab/abi/version.h>
#include <clothlab/abi/status.h>
#include <clothlab/abi/params.h>
#include <clothlab/abi/system.h>
#include <clothlab/abi/integrator.h>
#include <clothlab/abi/scenario.h>
#include <clothlab/abi/entry.h>
/* clang-format on */

#endif /* CLOTHLAB_PLUGIN_H */
