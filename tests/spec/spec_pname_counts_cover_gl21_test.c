/* tests/spec/spec_pname_counts_cover_gl21_test.c — test
 * spec_pname_counts_cover_gl21: for every spec command whose pointer count
 * is {pname: P}, every enum that gl.xml puts in P's group (GetPName for
 * glGet*v, LightParameter for glLightfv, ...) and that GL 1.0..2.1 defines
 * has an entry in pname_counts. A missing one would make a legal call an
 * error for the stream. gl.xml's groups are not complete, so this is a
 * floor, not the whole table.
 * Usage: spec_pname_counts_cover_gl21 SPEC.yaml GL.xml */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

#include "harness.h"

/* Legal GL 2.1 query enums whose result length is not fixed (it is the
 * value of another query), so no pname_counts entry can describe them. */
static const char *const variable_length[] = {
    "GL_COMPRESSED_TEXTURE_FORMATS", /* GL_NUM_COMPRESSED_TEXTURE_FORMATS values */
};

static int is_variable_length(const char *name)
{
    for (size_t i = 0; i < sizeof variable_length / sizeof variable_length[0]; i++)
        if (!strcmp(variable_length[i], name))
            return 1;
    return 0;
}

/* Listed under this name or under an alias with the same value. */
static int listed(const spec *s, const glxml *x, const glxml_enum *e)
{
    for (size_t i = 0; i < s->npnames; i++) {
        const glxml_enum *o = glxml_find_enum(x, s->pnames[i].name);
        if (o && o->value == e->value)
            return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    spec s;
    glxml x;
    int setup = spec_test_load_with_glxml(argc, argv, &s, &x);
    if (setup)
        return setup;

    size_t commands = 0, checked = 0;
    for (size_t i = 0; i < s.ncmds; i++) {
        const spec_command *c = &s.cmds[i];
        char glname[256];
        snprintf(glname, sizeof glname, "gl%s", c->name);
        const glxml_command *k = glxml_find_command(&x, glname);
        for (size_t j = 0; j < c->nparams; j++) {
            if (c->params[j].count.kind != SPEC_COUNT_PNAME)
                continue;
            const char *pname = c->params[j].count.args[0];
            const char *group = NULL;
            for (size_t m = 0; k && m < k->nparams; m++)
                if (!strcmp(k->params[m].name, pname))
                    group = k->params[m].group;
            CHECK(group, "%s:%d: %s: gl.xml gives parameter '%s' no enum group to check against", argv[1], c->line,
                  glname, pname);
            if (!group)
                continue;
            commands++;
            size_t members = 0;
            for (size_t e = 0; e < x.nenums; e++) {
                const glxml_enum *en = &x.enums[e];
                if (!en->gl_version || en->gl_version > 21 || !glxml_enum_in_group(en, group))
                    continue;
                members++;
                checked++;
                CHECK(listed(&s, &x, en) || is_variable_length(en->name),
                      "%s:%d: %s(%s) accepts %s (group %s, GL %d.%d) but pname_counts lacks it", argv[1], c->line,
                      glname, pname, en->name, group, en->gl_version / 10, en->gl_version % 10);
            }
            CHECK(members > 0, "%s:%d: %s: group %s has no GL <= 2.1 enums in gl.xml", argv[1], c->line, glname, group);
        }
    }
    printf("%zu enum-sized parameters, %zu (command, enum) pairs checked, %d missing\n", commands, checked,
           harness_failures);
    CHECK(commands > 0, "the spec has no {pname: ...} counts");
    glxml_free(&x);
    spec_free(&s);
    return harness_failures ? 1 : 0;
}
