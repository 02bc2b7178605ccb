/* mothership/ctl.c — the key=value codec of the control messages and the
 * chain their link=/option= fields carry (mothership/control.h). Owns
 * nothing beyond the buffers it returns. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "control.h"

void tsr_ctl_out_init(tsr_ctl_out *out) { memset(out, 0, sizeof *out); }

void tsr_ctl_out_free(tsr_ctl_out *out)
{
    free(out->text);
    memset(out, 0, sizeof *out);
}

static void append(tsr_ctl_out *out, const char *s, size_t n)
{
    if (out->failed)
        return;
    if (out->len + n + 1 > out->cap) {
        size_t cap = out->cap ? out->cap * 2 : 256;
        while (cap < out->len + n + 1)
            cap *= 2;
        char *text = realloc(out->text, cap);
        if (!text) {
            out->failed = 1;
            return;
        }
        out->text = text;
        out->cap = cap;
    }
    memcpy(out->text + out->len, s, n);
    out->len += n;
    out->text[out->len] = '\0';
}

void tsr_ctl_add(tsr_ctl_out *out, const char *key, const char *value)
{
    append(out, key, strlen(key));
    append(out, "=", 1);
    size_t start = out->len;
    append(out, value ? value : "", value ? strlen(value) : 0);
    for (size_t i = start; !out->failed && i < out->len; i++)
        if (out->text[i] == '\n' || out->text[i] == '\r')
            out->text[i] = ' ';
    append(out, "\n", 1);
}

void tsr_ctl_addf(tsr_ctl_out *out, const char *key, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    tsr_ctl_add(out, key, buf);
}

int tsr_ctl_parse(tsr_ctl *msg, const void *data, size_t len, tsr_error *err)
{
    memset(msg, 0, sizeof *msg);
    msg->text = malloc(len + 1);
    if (!msg->text)
        return tsr_error_set(err, TSR_ENOMEM, "control message of %zu bytes: out of memory", len);
    memcpy(msg->text, data, len);
    msg->text[len] = '\0';
    size_t fields = 1;
    for (const char *p = msg->text; (p = strchr(p, '\n')) != NULL; p++)
        fields++;
    msg->keys = malloc(fields * sizeof *msg->keys);
    msg->values = malloc(fields * sizeof *msg->values);
    if (!msg->keys || !msg->values) {
        tsr_ctl_free(msg);
        return tsr_error_set(err, TSR_ENOMEM, "control message of %zu fields: out of memory", fields);
    }
    char *line = msg->text;
    while (*line) {
        char *end = strchr(line, '\n');
        if (end)
            *end = '\0';
        if (*line) {
            char *eq = strchr(line, '=');
            if (!eq || eq == line) {
                tsr_error_set(err, TSR_EPROTO, "control message: line '%.60s' is not key=value", line);
                tsr_ctl_free(msg);
                return TSR_EPROTO;
            }
            *eq = '\0';
            msg->keys[msg->count] = line;
            msg->values[msg->count] = eq + 1;
            msg->count++;
        }
        if (!end)
            break;
        line = end + 1;
    }
    return TSR_OK;
}

void tsr_ctl_free(tsr_ctl *msg)
{
    free(msg->text);
    free(msg->keys);
    free(msg->values);
    msg->text = NULL;
    msg->keys = msg->values = NULL;
    msg->count = 0;
}

const char *tsr_ctl_get(const tsr_ctl *msg, const char *key)
{
    for (size_t i = 0; i < msg->count; i++)
        if (!strcmp(msg->keys[i], key))
            return msg->values[i];
    return NULL;
}

double tsr_ctl_number(const tsr_ctl *msg, const char *key, double fallback)
{
    const char *v = tsr_ctl_get(msg, key);
    if (!v || !*v)
        return fallback;
    char *end;
    double d = strtod(v, &end);
    return *end ? fallback : d;
}

void tsr_ctl_chain_free(tsr_ctl_chain *c)
{
    for (size_t i = 0; c->keys && i < c->option_count; i++)
        free((char *)c->keys[i]);
    free(c->links);
    free((void *)c->keys);
    free((void *)c->values);
    memset(c, 0, sizeof *c);
}

int tsr_ctl_chain_parse(const tsr_ctl *cfg, tsr_ctl_chain *c, tsr_error *err)
{
    memset(c, 0, sizeof *c);
    size_t links = 0, options = 0;
    for (size_t i = 0; i < cfg->count; i++) {
        links += !strcmp(cfg->keys[i], "link");
        options += !strcmp(cfg->keys[i], "option");
    }
    if (!links)
        return tsr_error_set(err, TSR_EPROTO, "CONFIG without link= (the chain)");
    c->links = calloc(links, sizeof *c->links);
    c->keys = calloc(options ? options : 1, sizeof *c->keys);
    c->values = calloc(options ? options : 1, sizeof *c->values);
    if (!c->links || !c->keys || !c->values) {
        tsr_ctl_chain_free(c);
        return tsr_error_set(err, TSR_ENOMEM, "CONFIG: out of memory for the chain");
    }
    for (size_t i = 0; i < cfg->count; i++) {
        if (!strcmp(cfg->keys[i], "link")) {
            c->links[c->count++] = (tsr_chain_link){
                .spu = cfg->values[i], .keys = c->keys + c->option_count, .values = c->values + c->option_count};
            continue;
        }
        if (strcmp(cfg->keys[i], "option"))
            continue;
        const char *v = cfg->values[i];
        size_t key_len = strcspn(v, "=");
        if (!c->count || !v[key_len] || !key_len) {
            tsr_ctl_chain_free(c);
            return tsr_error_set(err, TSR_EPROTO, "CONFIG: option='%.60s' %s", v,
                                 c->count ? "is not KEY=VALUE" : "comes before any link=");
        }
        char *key = strndup(v, key_len);
        if (!key) {
            tsr_ctl_chain_free(c);
            return tsr_error_set(err, TSR_ENOMEM, "CONFIG: out of memory for the chain");
        }
        c->keys[c->option_count] = key;
        c->values[c->option_count++] = v + key_len + 1;
        c->links[c->count - 1].option_count++;
    }
    return TSR_OK;
}

const char *tsr_ctl_kind_name(unsigned kind)
{
    switch (kind) {
    case TSR_MS_MSG_JOIN: return "JOIN";
    case TSR_MS_MSG_READY: return "READY";
    case TSR_MS_MSG_STATS: return "STATS";
    case TSR_MS_MSG_DONE: return "DONE";
    case TSR_MS_MSG_CONFIG: return "CONFIG";
    case TSR_MS_MSG_STOP: return "STOP";
    case TSR_MS_MSG_REFUSE: return "REFUSE";
    case TSR_MS_MSG_LINKS: return "LINKS";
    default: return "unknown";
    }
}
