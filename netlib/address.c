/* netlib/address.c — text addresses ("tcp://[::1]:7000", "unix:/p", "inproc:n").
 * Owns: parsing them into net_address and formatting socket addresses back.
 * Never: resolves host names (the caller does, with a bounded time) or
 * accepts a port, path or name it would have to truncate. */
#include <arpa/inet.h>
#include <netinet/in.h>
#include <stdio.h>
#include <string.h>

#include "net_internal.h"

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

int net_address_parse(const char *text, net_address *out, tsr_error *err)
{
    memset(out, 0, sizeof *out);
    if (!text)
        return tsr_error_set(err, TSR_EINVAL, "net: no address given");
    if (!strncmp(text, "tcp://", 6)) {
        out->transport = NET_TCP;
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
        out->transport = NET_UNIX;
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
        out->transport = NET_INPROC;
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

void net_address_format_sockaddr(const struct sockaddr *sa, enum net_transport t, char *out, size_t size)
{
    char ip[INET6_ADDRSTRLEN] = "?";
    if (t == NET_TCP && sa->sa_family == AF_INET) {
        const struct sockaddr_in *in = (const struct sockaddr_in *)sa;
        inet_ntop(AF_INET, &in->sin_addr, ip, sizeof ip);
        snprintf(out, size, "tcp://%s:%u", ip, ntohs(in->sin_port));
    } else if (t == NET_TCP && sa->sa_family == AF_INET6) {
        const struct sockaddr_in6 *in6 = (const struct sockaddr_in6 *)sa;
        inet_ntop(AF_INET6, &in6->sin6_addr, ip, sizeof ip);
        snprintf(out, size, "tcp://[%s]:%u", ip, ntohs(in6->sin6_port));
    } else {
        snprintf(out, size, "unknown");
    }
}
