/* netlib/address.c — text addresses ("tcp://[::1]:7000", "unix:/p",
 * "inproc:n"), the one place they are parsed, checked, printed and
 * normalised (tessera/dev/net.h, addresses): for netlib itself, the graph
 * model's listen places, the mothership and the programs. Owns: parsing
 * them into tsr_net_address and writing them (and socket addresses) back.
 * Never: resolves host names (the caller does, with a bounded time),
 * accepts a port, path or name it would have to truncate, or needs more
 * of netlib than its header (the graph fuzzer compiles it alone). */
#include <arpa/inet.h>
#include <ctype.h>
#include <errno.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/un.h>

#include "tessera/dev/net.h"

void net_address_format_sockaddr(const struct sockaddr *sa, tsr_net_transport t, char *out, size_t size);

_Static_assert(sizeof(((struct sockaddr_un *)0)->sun_path) == TSR_NET_UNIX_PATH_MAX + 1,
               "TSR_NET_UNIX_PATH_MAX is sun_path less its NUL");

static int bad_address(tsr_error *err, const char *text, const char *why)
{
    return tsr_error_set(err, TSR_EINVAL,
                         "net: bad address '%s': %s (expected tcp://HOST:PORT, "
                         "tcp://[IPV6]:PORT, unix:PATH or inproc:NAME)",
                         text, why);
}

static int parse_port(const char *s, unsigned *port)
{
    if (!*s)
        return -1;
    unsigned v = 0;
    for (; *s; s++) {
        if (*s < '0' || *s > '9')
            return -1;
        v = v * 10 + (unsigned)(*s - '0');
        if (v > 65535)
            return -1;
    }
    *port = v;
    return 0;
}

int tsr_net_address_parse(const char *text, tsr_net_address *out, tsr_error *err)
{
    memset(out, 0, sizeof *out);
    if (!text)
        return tsr_error_set(err, TSR_EINVAL, "net: no address given");
    if (!strncmp(text, "tcp://", 6)) {
        out->transport = TSR_NET_TCP;
        const char *hostport = text + 6;
        const char *colon;
        if (*hostport == '[') {
            const char *close = strchr(hostport, ']');
            if (!close)
                return bad_address(err, text, "'[' without ']'");
            size_t n = (size_t)(close - hostport - 1);
            if (n == 0 || n >= sizeof out->host)
                return bad_address(err, text, "empty or too long IPv6 address");
            memcpy(out->host, hostport + 1, n);
            struct in6_addr probe;
            if (inet_pton(AF_INET6, out->host, &probe) != 1)
                return bad_address(err, text, "not an IPv6 address between [ ]");
            if (close[1] != ':')
                return bad_address(err, text, "missing ':PORT' after ']'");
            colon = close + 1;
        } else {
            colon = strrchr(hostport, ':');
            if (!colon)
                return bad_address(err, text, "missing ':PORT'");
            size_t n = (size_t)(colon - hostport);
            if (n >= sizeof out->host)
                return bad_address(err, text, "host name too long");
            memcpy(out->host, hostport, n);
            if (memchr(out->host, ':', n))
                return bad_address(err, text, "IPv6 addresses need brackets");
        }
        if (parse_port(colon + 1, &out->port))
            return bad_address(err, text, "port must be a number 0..65535");
        return TSR_OK;
    }
    if (!strncmp(text, "unix:", 5)) {
        out->transport = TSR_NET_UNIX;
        const char *path = text + 5;
        if (!strncmp(path, "//", 2))
            path += 2; /* tolerate unix:///tmp/x */
        if (!*path)
            return bad_address(err, text, "empty socket path");
        if (strlen(path) >= sizeof out->path)
            return bad_address(err, text, "socket path longer than 107 bytes");
        strcpy(out->path, path);
        return TSR_OK;
    }
    if (!strncmp(text, "inproc:", 7)) {
        out->transport = TSR_NET_INPROC;
        const char *name = text + 7;
        if (!*name)
            return bad_address(err, text, "empty in-process name");
        if (strlen(name) >= sizeof out->name)
            return bad_address(err, text, "in-process name too long");
        strcpy(out->name, name);
        return TSR_OK;
    }
    return bad_address(err, text, "unknown transport");
}

void net_address_format_sockaddr(const struct sockaddr *sa, tsr_net_transport t, char *out, size_t size)
{
    char ip[INET6_ADDRSTRLEN] = "?";
    if (t == TSR_NET_TCP && sa->sa_family == AF_INET) {
        const struct sockaddr_in *in = (const struct sockaddr_in *)sa;
        inet_ntop(AF_INET, &in->sin_addr, ip, sizeof ip);
        snprintf(out, size, "tcp://%s:%u", ip, ntohs(in->sin_port));
    } else if (t == TSR_NET_TCP && sa->sa_family == AF_INET6) {
        const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)sa;
        inet_ntop(AF_INET6, &in6->sin6_addr, ip, sizeof ip);
        snprintf(out, size, "tcp://[%s]:%u", ip, ntohs(in6->sin6_port));
    } else {
        snprintf(out, size, "unknown");
    }
}

static int too_long(tsr_error *err, const char *what, size_t size)
{
    return tsr_error_set(err, TSR_EINVAL, "net: the address of %.200s does not fit in %zu bytes", what, size);
}

int tsr_net_address_format(const tsr_net_address *a, char *out, size_t size, tsr_error *err)
{
    int n;
    switch (a->transport) {
    case TSR_NET_TCP: {
        int v6 = strchr(a->host, ':') != NULL;
        n = snprintf(out, size, "tcp://%s%s%s:%u", v6 ? "[" : "", a->host, v6 ? "]" : "", a->port);
        break;
    }
    case TSR_NET_UNIX: n = snprintf(out, size, "unix:%s", a->path); break;
    case TSR_NET_INPROC: n = snprintf(out, size, "inproc:%s", a->name); break;
    default: return tsr_error_set(err, TSR_EINVAL, "net: address of unknown transport %d", (int)a->transport);
    }
    return n < 0 || (size_t)n >= size ? too_long(err, "a parsed address", size) : TSR_OK;
}

int tsr_net_address_tcp(const char *host, const char *port, char *out, size_t size, tsr_error *err)
{
    int v6 = strchr(host, ':') && host[0] != '[';
    int n = snprintf(out, size, "tcp://%s%s%s:%s", v6 ? "[" : "", host, v6 ? "]" : "", port);
    return n < 0 || (size_t)n >= size ? too_long(err, host, size) : TSR_OK;
}

int tsr_net_address_normalise(const char *text, char *out, size_t size, tsr_error *err)
{
    int netlib = !strncmp(text, "tcp://", 6) || !strncmp(text, "unix:", 5) || !strncmp(text, "inproc:", 7);
    int n = snprintf(out, size, "%s%s", netlib ? "" : "tcp://", text);
    return n < 0 || (size_t)n >= size ? too_long(err, text, size) : TSR_OK;
}

static int listen_spec_tcp(const char *who, const char *text, tsr_net_address *out, tsr_error *err)
{
    const char *port = text;
    const char *colon = strrchr(text, ':');
    if (text[0] == '[') {
        const char *close = strchr(text, ']');
        char v6[INET6_ADDRSTRLEN];
        struct in6_addr probe;
        if (!close || close[1] != ':' || close == text + 1 || (size_t)(close - text - 1) >= sizeof v6 ||
            (snprintf(v6, sizeof v6, "%.*s", (int)(close - text - 1), text + 1), inet_pton(AF_INET6, v6, &probe) != 1))
            return tsr_error_set(err, TSR_EINVAL, "%s: '%.80s' is not [IPv6]:PORT", who, text);
        snprintf(out->host, sizeof out->host, "%s", v6);
        port = close + 2;
    } else if (colon) {
        if (colon == text || memchr(text, ':', (size_t)(colon - text)))
            return tsr_error_set(err, TSR_EINVAL, "%s: '%.80s' is not HOST:PORT (write IPv6 as [ADDR]:PORT)", who,
                                 text);
        if ((size_t)(colon - text) >= sizeof out->host)
            return tsr_error_set(err, TSR_EINVAL, "%s: the host is %zu bytes, the limit is %zu", who,
                                 (size_t)(colon - text), sizeof out->host - 1);
        memcpy(out->host, text, (size_t)(colon - text));
        port = colon + 1;
    }
    char *end;
    errno = 0;
    long p = strtol(port, &end, 10);
    if (!*port || *end || !isdigit((unsigned char)*port) || errno == ERANGE || p > 65535)
        return tsr_error_set(err, TSR_EINVAL, "%s: port '%.20s' in '%.80s' is not a number in [0, 65535]", who, port,
                             text);
    out->port = (unsigned)p;
    return TSR_OK;
}

int tsr_net_listen_spec_parse(const char *who, const char *spec, tsr_net_transport transport, tsr_net_address *out,
                              tsr_error *err)
{
    memset(out, 0, sizeof *out);
    out->transport = transport;
    if (!spec)
        return tsr_error_set(err, TSR_EINVAL, "%s: no listen place given", who);
    if (transport == TSR_NET_UNIX) {
        if (strlen(spec) > TSR_NET_UNIX_PATH_MAX)
            return tsr_error_set(err, TSR_EINVAL, "%s: unix socket path is %zu bytes, the limit is %d", who,
                                 strlen(spec), TSR_NET_UNIX_PATH_MAX);
        memcpy(out->path, spec, strlen(spec) + 1);
        return TSR_OK;
    }
    if (transport != TSR_NET_TCP)
        return tsr_error_set(err, TSR_EINVAL, "%s: a listen place is tcp or unix", who);
    return listen_spec_tcp(who, spec, out, err);
}
