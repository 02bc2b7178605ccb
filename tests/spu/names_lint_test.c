/* tests/spu/names_lint_test.c — the core knows no SPU by name. Reads every C
 * source and header under the directories given (core/, mothership/, cli/,
 * client/, server/) with a small C lexer (comments skipped, string
 * literals and identifiers as tokens) and reports, as FILE:LINE: ..., each
 *   - string literal or identifier naming a built-in SPU: the names that
 *     mean nothing else (replicate, tilesort, readback, binaryswap,
 *     passthrough) as a word of a literal or a '_'-separated part of an
 *     identifier; the names that are also ordinary words (pack, render,
 *     print, loopback: packing, render time, printf, the loopback
 *     interface) only as a literal that names the SPU the way chain text
 *     does: the name alone, or at the start or after '!', followed by the
 *     end, '!' or an option (" key=");
 *   - role guessed from an option name: a literal that is exactly one of
 *     server, servers, token, tiles, rank, peers, display inside a
 *     statement that deals with SPU options (an identifier containing
 *     "option", or `keys[`/`values[`). Those words as control-message
 *     fields or graph keys are not option lookups and pass.
 * Exit 0 when nothing is found, 1 with one line per finding, 2 on usage or
 * I/O errors. Usage: names_lint DIR_OR_FILE... */
#define _DEFAULT_SOURCE /* DT_DIR, DT_REG */
#include <ctype.h>
#include <dirent.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *const distinct_names[] = {"replicate", "tilesort", "readback", "binaryswap", "passthrough"};
static const char *const word_names[] = {"pack", "render", "print", "loopback"};
static const char *const role_options[] = {"server", "servers", "token", "tiles", "rank", "peers", "display"};
#define COUNT(a) (sizeof a / sizeof a[0])

static int findings;

typedef enum { TOK_STRING, TOK_IDENT, TOK_PUNCT } tok_kind;

typedef struct token {
    tok_kind kind;
    char *text; /* a literal's contents (escapes as written), an identifier, or one character */
    int line;
} token;

/* One statement's tokens (from after the last ';', '{' or '}'). */
typedef struct statement {
    token *items;
    size_t count, cap;
} statement;

static void report(const char *file, int line, const char *fmt, const char *what)
{
    printf("%s:%d: ", file, line);
    printf(fmt, what);
    printf("\n");
    findings++;
}

static bool is_word_char(char c) { return isalnum((unsigned char)c) || c == '_'; }

/* `word` appears in `s` with no letter, digit or '_' on either side. */
static bool has_word(const char *s, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = strstr(s, word); p; p = strstr(p + 1, word))
        if ((p == s || !is_word_char(p[-1])) && !is_word_char(p[n]))
            return true;
    return false;
}

/* `name` as a '_'-separated part of identifier `id`, in any case. */
static bool has_part(const char *id, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = id; *p;) {
        size_t len = strcspn(p, "_");
        if (len == n && !strncasecmp(p, name, n))
            return true;
        p += len + (p[len] == '_');
    }
    return false;
}

/* After an SPU's name in chain text: the end, '!' or " key=". */
static bool ends_chain_name(const char *p)
{
    while (*p == ' ')
        p++;
    if (*p == '\0' || *p == '!')
        return true;
    size_t key = 0;
    while (islower((unsigned char)p[key]) || isdigit((unsigned char)p[key]) || p[key] == '_')
        key++;
    return key > 0 && p[key] == '=';
}

/* The literal names SPU `name` the way chain text does. */
static bool names_spu(const char *s, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = s;; p++) {
        while (*p == ' ')
            p++;
        if (!strncmp(p, name, n) && (p[n] == '\0' || p[n] == '!' || (p[n] == ' ' && ends_chain_name(p + n))))
            return true;
        p = strchr(p, '!');
        if (!p)
            return false;
    }
}

static bool deals_with_options(const statement *st)
{
    for (size_t i = 0; i < st->count; i++) {
        const token *t = &st->items[i];
        if (t->kind != TOK_IDENT)
            continue;
        char lower[256];
        snprintf(lower, sizeof lower, "%s", t->text);
        for (char *c = lower; *c; c++)
            *c = (char)tolower((unsigned char)*c);
        if (strstr(lower, "option"))
            return true;
        if ((!strcmp(t->text, "keys") || !strcmp(t->text, "values")) && i + 1 < st->count &&
            st->items[i + 1].kind == TOK_PUNCT && st->items[i + 1].text[0] == '[')
            return true;
    }
    return false;
}

static void check_statement(const char *file, statement *st)
{
    bool options = deals_with_options(st);
    for (size_t i = 0; i < st->count; i++) {
        const token *t = &st->items[i];
        if (t->kind == TOK_IDENT) {
            for (size_t k = 0; k < COUNT(distinct_names); k++)
                if (has_part(t->text, distinct_names[k]))
                    report(file, t->line, "identifier '%s' names a built-in SPU", t->text);
            continue;
        }
        if (t->kind != TOK_STRING)
            continue;
        for (size_t k = 0; k < COUNT(distinct_names); k++)
            if (has_word(t->text, distinct_names[k]))
                report(file, t->line, "string literal \"%s\" names a built-in SPU", t->text);
        for (size_t k = 0; k < COUNT(word_names); k++)
            if (names_spu(t->text, word_names[k]))
                report(file, t->line, "string literal \"%s\" names a built-in SPU", t->text);
        for (size_t k = 0; options && k < COUNT(role_options); k++)
            if (!strcmp(t->text, role_options[k]))
                report(file, t->line,
                       "string literal \"%s\" looks an SPU option up by name: a role guessed "
                       "from an option name (declare it in tsr_spu_class.network)",
                       t->text);
    }
    for (size_t i = 0; i < st->count; i++)
        free(st->items[i].text);
    st->count = 0;
}

static void push(statement *st, tok_kind kind, const char *text, size_t len, int line)
{
    if (st->count == st->cap) {
        st->cap = st->cap ? 2 * st->cap : 64;
        st->items = realloc(st->items, st->cap * sizeof *st->items);
        if (!st->items) {
            fprintf(stderr, "names_lint: out of memory\n");
            exit(2);
        }
    }
    char *copy = malloc(len + 1);
    if (!copy) {
        fprintf(stderr, "names_lint: out of memory\n");
        exit(2);
    }
    memcpy(copy, text, len);
    copy[len] = '\0';
    st->items[st->count++] = (token){kind, copy, line};
}

static void lint_text(const char *file, const char *s)
{
    statement st = {0};
    int line = 1;
    for (const char *p = s; *p;) {
        if (*p == '\n') {
            line++;
            p++;
        } else if (p[0] == '/' && p[1] == '*') {
            const char *end = strstr(p + 2, "*/");
            const char *stop = end ? end + 2 : p + strlen(p);
            for (; p < stop; p++)
                line += *p == '\n';
        } else if (p[0] == '/' && p[1] == '/') {
            p += strcspn(p, "\n");
        } else if (*p == '"' || *p == '\'') {
            char quote = *p++;
            const char *start = p;
            while (*p && *p != quote && *p != '\n')
                p += p[0] == '\\' && p[1] ? 2 : 1;
            if (quote == '"')
                push(&st, TOK_STRING, start, (size_t)(p - start), line);
            if (*p == quote)
                p++;
        } else if (isalpha((unsigned char)*p) || *p == '_') {
            const char *start = p;
            while (is_word_char(*p))
                p++;
            push(&st, TOK_IDENT, start, (size_t)(p - start), line);
        } else if (isdigit((unsigned char)*p)) {
            while (is_word_char(*p) || *p == '.')
                p++;
        } else {
            if (*p == ';' || *p == '{' || *p == '}')
                check_statement(file, &st);
            else if (!isspace((unsigned char)*p))
                push(&st, TOK_PUNCT, p, 1, line);
            p++;
        }
    }
    check_statement(file, &st);
    free(st.items);
}

static bool is_c_file(const char *path)
{
    size_t n = strlen(path);
    return (n > 2 && !strcmp(path + n - 2, ".c")) || (n > 2 && !strcmp(path + n - 2, ".h"));
}

static int lint_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "names_lint: cannot open %s\n", path);
        return 2;
    }
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, 0, SEEK_SET);
    char *text = malloc((size_t)size + 1);
    size_t got = text ? fread(text, 1, (size_t)size, f) : 0;
    fclose(f);
    if (!text || got != (size_t)size) {
        free(text);
        fprintf(stderr, "names_lint: cannot read %s\n", path);
        return 2;
    }
    text[size] = '\0';
    lint_text(path, text);
    free(text);
    return 0;
}

static int compare_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

/* Files in a stable order, so the report reads the same every time. */
static int lint_path(const char *path, size_t *files)
{
    struct stat sb;
    if (stat(path, &sb) != 0) {
        fprintf(stderr, "names_lint: no such file or directory: %s\n", path);
        return 2;
    }
    if (!S_ISDIR(sb.st_mode)) {
        if (!is_c_file(path))
            return 0;
        (*files)++;
        return lint_file(path);
    }
    DIR *d = opendir(path);
    if (!d) {
        fprintf(stderr, "names_lint: cannot read directory %s\n", path);
        return 2;
    }
    char **names = NULL;
    size_t count = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (e->d_name[0] == '.')
            continue;
        if (count == cap) {
            cap = cap ? 2 * cap : 32;
            char **grown = realloc(names, cap * sizeof *names);
            if (!grown)
                break;
            names = grown;
        }
        size_t len = strlen(path) + strlen(e->d_name) + 2;
        if (!(names[count] = malloc(len)))
            break;
        snprintf(names[count++], len, "%s/%s", path, e->d_name);
    }
    closedir(d);
    qsort(names, count, sizeof *names, compare_names);
    int rc = 0;
    for (size_t i = 0; i < count; i++) {
        int r = lint_path(names[i], files);
        rc = r > rc ? r : rc;
        free(names[i]);
    }
    free(names);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s DIR_OR_FILE...\n", argv[0]);
        return 2;
    }
    size_t files = 0;
    int rc = 0;
    for (int i = 1; i < argc; i++) {
        int r = lint_path(argv[i], &files);
        rc = r > rc ? r : rc;
    }
    if (rc)
        return rc;
    if (files == 0) {
        fprintf(stderr, "names_lint: no C files under the paths given\n");
        return 2;
    }
    printf("names_lint: %zu files, %d finding%s\n", files, findings, findings == 1 ? "" : "s");
    return findings ? 1 : 0;
}
