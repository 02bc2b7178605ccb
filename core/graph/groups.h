/* core/graph/groups.h — the rules for sort-last compositing groups in a
 * graph (groups.c), called by the graph loader (graph.c) once roles are
 * checked. Private to libtessera_graph. */
#ifndef TSR_CORE_GRAPH_GROUPS_H
#define TSR_CORE_GRAPH_GROUPS_H

#include "tessera/error.h"
#include "tessera/graph.h"

/* Checks every group of peers (the nodes whose network SPU has
 * TSR_SPU_ROLE_PEERS and sends to one display node). TSR_EINVAL with
 * "file:line:column: ..." at the node at fault. `flags` are the loader's
 * (TSR_GRAPH_NO_SPU_CHECK: nodes whose SPUs are not installed are skipped). */
int tsr_graph_check_groups(const tsr_graph *graph, unsigned flags, tsr_error *err);

#endif
