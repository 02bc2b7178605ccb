/* mothership/faker.c — faker.h: reads only the section headers, the
 * dynamic section and its string table of a 64-bit ELF file, each read
 * bounded by the file's size. */
#include <elf.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "faker.h"

static bool read_at(FILE *f, long off, void *buf, size_t n)
{
    return off >= 0 && fseek(f, off, SEEK_SET) == 0 && fread(buf, 1, n, f) == n;
}

bool tsr_ms_links_tessera_gl(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return false;
    bool found = false;
    Elf64_Ehdr eh;
    if (!read_at(f, 0, &eh, sizeof eh) || memcmp(eh.e_ident, ELFMAG, SELFMAG) != 0 ||
        eh.e_ident[EI_CLASS] != ELFCLASS64 || eh.e_shentsize != sizeof(Elf64_Shdr) || eh.e_shnum > 4096)
        goto done;
    for (unsigned i = 0; i < eh.e_shnum && !found; i++) {
        Elf64_Shdr sh, str;
        if (!read_at(f, (long)(eh.e_shoff + (uint64_t)i * sizeof sh), &sh, sizeof sh))
            break;
        if (sh.sh_type != SHT_DYNAMIC || sh.sh_link >= eh.e_shnum ||
            !read_at(f, (long)(eh.e_shoff + (uint64_t)sh.sh_link * sizeof str), &str, sizeof str) ||
            sh.sh_size > (1u << 20) || str.sh_size > (1u << 24))
            continue;
        Elf64_Dyn *dyn = malloc(sh.sh_size ? sh.sh_size : 1);
        char *strtab = malloc(str.sh_size + 1);
        if (dyn && strtab && read_at(f, (long)sh.sh_offset, dyn, sh.sh_size) &&
            read_at(f, (long)str.sh_offset, strtab, str.sh_size)) {
            strtab[str.sh_size] = '\0';
            for (size_t k = 0; k < sh.sh_size / sizeof *dyn && dyn[k].d_tag != DT_NULL; k++)
                if (dyn[k].d_tag == DT_NEEDED && dyn[k].d_un.d_val < str.sh_size &&
                    !strncmp(strtab + dyn[k].d_un.d_val, "libtessera_gl.so", 16))
                    found = true;
        }
        free(dyn);
        free(strtab);
    }
done:
    fclose(f);
    return found;
}

const char *tsr_ms_faker_dir(void)
{
    const char *dir = getenv("TESSERA_FAKER_DIR");
    if (!dir || !dir[0])
        return NULL;
    char path[4096];
    snprintf(path, sizeof path, "%s/libGL.so.1", dir);
    return access(path, R_OK) == 0 ? dir : NULL;
}
