/* tests/spec/spec_opcodes_frozen_test.c — test spec_opcodes_frozen: every
 * "Name opcode" line of tests/data/opcodes.txt still holds in the spec.
 * Adding commands is fine; renumbering or removing one breaks the wire
 * protocol for every peer built before the change.
 * Usage: spec_opcodes_frozen SPEC.yaml opcodes.txt */
#include "spec_test_setup.h"

#include <stdio.h>
#include <string.h>

#include "harness.h"

int main(int argc, char **argv)
{
    spec s;
    FILE *f;
    int setup = spec_test_load_with_file(argc, argv, "opcodes.txt", &s, &f);
    if (setup)
        return setup;
    char line[256];
    int lineno = 0, frozen = 0;
    while (fgets(line, sizeof line, f)) {
        lineno++;
        char name[200];
        int opcode;
        char extra;
        if (line[0] == '#' || line[strspn(line, " \t\r\n")] == 0)
            continue;
        int fields = sscanf(line, "%199s %d %c", name, &opcode, &extra);
        CHECK(fields == 2, "%s:%d: expected 'Name opcode'", argv[2], lineno);
        if (fields != 2)
            continue;
        frozen++;
        const spec_command *c = spec_find(&s, name);
        CHECK(c, "%s:%d: %s (opcode %d) was removed from the spec", argv[2], lineno, name, opcode);
        if (c)
            CHECK(c->opcode == opcode, "%s:%d: %s was renumbered from %d to %d (spec line %d)", argv[2], lineno, name,
                  opcode, c->opcode, c->line);
    }
    fclose(f);
    printf("%d frozen opcodes, %d broken, %zu commands in the spec\n", frozen, harness_failures, s.ncmds);
    CHECK(frozen > 0, "%s freezes nothing", argv[2]);
    spec_free(&s);
    return harness_failures ? 1 : 0;
}
