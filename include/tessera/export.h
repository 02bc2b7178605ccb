/* tessera/export.h — symbol visibility for the public API. libtessera is
 * built with -fvisibility=hidden; only TSR_API symbols are exported. */
#ifndef TESSERA_EXPORT_H
#define TESSERA_EXPORT_H
#define TSR_API __attribute__((visibility("default")))
#endif
