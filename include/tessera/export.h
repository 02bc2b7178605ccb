/* tessera/export.h — symbol visibility for the public API. libtessera,
 * libtessera_client, libtessera_graph and libtessera_gl are built with
 * -fvisibility=hidden; only TSR_API symbols are exported, and TSR_API goes
 * only on what an installed header declares (test api_exports_match_headers). */
#ifndef TESSERA_EXPORT_H
#define TESSERA_EXPORT_H
#define TSR_API __attribute__((visibility("default")))
#endif
