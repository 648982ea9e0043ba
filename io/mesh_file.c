/* mesh_file.c — mesh files by extension: what the path is, Colibri's own readers of OFF and PLY,
 * and the adapter to OpenMesh for STL and OBJ and for writing.
 *
 * OFF and PLY are read here rather than by OpenMesh 9.0, whose readers of these formats do not
 * test their stream after reading a number: a file cut short, a header promising more faces than
 * follow, or a "nan" coordinate were read on with stale or uninitialised values (vertex indices
 * like -722932768), and a PLY header cut short made its header loop run for ever. These
 * readers read every number the header announces, check each one, and name the file and line
 * (the byte offset in binary files) of the first problem. */
#define _POSIX_C_SOURCE 200809L /* stat */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "io/mesh.h"
#include "io/mesh_openmesh.h"

cb_status cb_mesh_format_of_path(cb_mesh_format *fmt, const char *path, cb_error *err)
{
    static const struct {
        const char *ext;
        cb_mesh_format fmt;
    } known[] = {{"stl", CB_MESH_STL}, {"obj", CB_MESH_OBJ}, {"ply", CB_MESH_PLY},
                 {"off", CB_MESH_OFF}};
    const char *dot = strrchr(path, '.');
    for (size_t k = 0; dot && k < sizeof known / sizeof *known; k++)
        if (!strcasecmp(dot + 1, known[k].ext)) {
            *fmt = known[k].fmt;
            return CB_OK;
        }
    return cb_error_set(err, CB_ERR_UNSUPPORTED,
                        "%s: unknown mesh format (known: .stl, .obj, .ply, .off)", path);
}

cb_status cb_mesh_write(const char *path, const cb_mesh_t mesh, const cb_mesh_write_options *opt,
                        cb_error *err)
{
    cb_mesh_format fmt;
    cb_status st = cb_mesh_format_of_path(&fmt, path, err);
    if (st)
        return st;
    /* OpenMesh only says that it failed; opening here first gives the user the reason. */
    FILE *f = fopen(path, "wb");
    if (!f)
        return cb_error_set(err, CB_ERR_IO, "%s: cannot create: %s", path, strerror(errno));
    fclose(f);
    return cb_mesh_openmesh_write(path, mesh, fmt == CB_MESH_STL && !(opt && opt->stl_ascii),
                                  err);
}

/* ---------------------------------------------------------------- the input stream --------- */

enum {
    CHUNK = 1 << 16,
    TOKEN_MAX = 256, /* longer than any number: a longer token is not one */
    LINE_MAX_PLY = 4096
};

/* A buffered input with a position for messages: the line (text) or byte offset (binary) of
 * what was read last, and one token of look-ahead. */
typedef struct {
    FILE *f;
    const char *path;
    long long size; /* bytes in the file */
    unsigned char buf[CHUNK];
    size_t pos, len;
    long long offset; /* bytes before buf */
    long line;        /* line of the next byte */
    long tok_line;    /* line of the last token read */
    int binary;       /* messages give byte offsets */
    int read_error;   /* errno of a failed read, 0 when none */
    char pending[TOKEN_MAX];
    long pending_line;
    int has_pending;
    cb_error *err;
    cb_mesh_struct *m;
} src;

static int src_fill(src *s)
{
    if (s->pos < s->len)
        return 1;
    s->offset += (long long)s->len;
    s->pos = 0;
    s->len = fread(s->buf, 1, CHUNK, s->f);
    if (s->len == 0 && ferror(s->f) && !s->read_error)
        s->read_error = errno ? errno : EIO;
    return s->len > 0;
}

static int src_get(src *s)
{
    if (!src_fill(s))
        return -1;
    int c = s->buf[s->pos++];
    s->line += c == '\n';
    return c;
}

static int src_peek(src *s)
{
    return src_fill(s) ? s->buf[s->pos] : -1;
}

static long long src_offset(const src *s)
{
    return s->offset + (long long)s->pos;
}

/* Records a problem at the current place: "file:line: ..." or "file: byte N: ...". A read
 * error of the system takes precedence, as it is the cause of whatever was read wrong. */
static cb_status fail(src *s, cb_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static cb_status fail(src *s, cb_status st, const char *fmt, ...)
{
    if (s->read_error)
        return cb_error_set(s->err, CB_ERR_IO, "%s: read error: %s", s->path,
                            strerror(s->read_error));
    char msg[CB_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (s->binary)
        return cb_error_set(s->err, st, "%s: byte %lld: %s", s->path, src_offset(s), msg);
    return cb_error_set(s->err, st, "%s:%ld: %s", s->path, s->tok_line, msg);
}

/* The token as a message may show it: at most 24 characters, non-printable ones as '?'. */
static const char *shown(const char *tok, char out[32])
{
    size_t n = 0;
    for (; tok[n] && n < 24; n++)
        out[n] = tok[n] > ' ' && tok[n] < 127 ? tok[n] : '?';
    strcpy(out + n, tok[n] ? "..." : "");
    return out;
}

static int is_space(int c)
{
    return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/* Skips the rest of the current line, its end included. */
static void skip_line(src *s)
{
    int c;
    while ((c = src_get(s)) >= 0 && c != '\n')
        ;
}

/* The next whitespace-separated token, skipping '#' comments to the end of their line when
 * comments is set. Returns 1, 0 at the end of the file, -1 (error set) for a token too long to
 * be a number. */
static int next_token(src *s, char tok[TOKEN_MAX], int comments)
{
    if (s->has_pending) {
        s->has_pending = 0;
        memcpy(tok, s->pending, TOKEN_MAX);
        s->tok_line = s->pending_line;
        return 1;
    }
    int c;
    for (;;) {
        while ((c = src_peek(s)) >= 0 && is_space(c))
            src_get(s);
        if (c == '#' && comments)
            skip_line(s);
        else
            break;
    }
    if (c < 0)
        return 0;
    s->tok_line = s->line;
    int n = 0;
    while ((c = src_peek(s)) >= 0 && !is_space(c)) {
        if (n == TOKEN_MAX - 1) {
            tok[n] = '\0';
            char buf[32];
            fail(s, CB_ERR_PARSE, "'%s' is too long to be a number", shown(tok, buf));
            return -1;
        }
        /* A NUL byte would end the token for the parsers: keep it as a character no number
         * holds. */
        c = src_get(s);
        tok[n++] = c ? (char)c : '?';
    }
    tok[n] = '\0';
    return 1;
}

static void push_back(src *s, const char tok[TOKEN_MAX])
{
    memcpy(s->pending, tok, TOKEN_MAX);
    s->pending_line = s->tok_line;
    s->has_pending = 1;
}

/* A finite decimal real taking the whole token. Hexadecimal, inf and nan are refused: no
 * writer of these formats produces them, and they are what a corrupted file holds. */
static int parse_real(const char *tok, double *x)
{
    if (!*tok || strspn(tok, "0123456789+-.eE") != strlen(tok))
        return 0;
    char *end;
    *x = strtod(tok, &end);
    return *end == '\0' && isfinite(*x);
}

/* A whole number in [lo, hi] taking the whole token. */
static int parse_int(const char *tok, long long lo, long long hi, long long *v)
{
    const char *digits = tok + (*tok == '-' || *tok == '+');
    if (!*digits || strspn(digits, "0123456789") != strlen(digits))
        return 0;
    errno = 0;
    char *end;
    long long x = strtoll(tok, &end, 10);
    if (errno || *end || x < lo || x > hi)
        return 0;
    *v = x;
    return 1;
}

/* Reads n bytes; 0 when the file ends first. */
static int read_bytes(src *s, unsigned char *out, size_t n)
{
    for (size_t k = 0; k < n; k++) {
        int c = src_get(s);
        if (c < 0)
            return 0;
        out[k] = (unsigned char)c;
    }
    return 1;
}

/* Appends a triangle read at the current place, the message naming the face. */
static cb_status add_triangle(src *s, int face, const long long v[3])
{
    cb_error e;
    cb_status st = cb_mesh_append_triangle(s->m, (int)v[0], (int)v[1], (int)v[2], &e);
    if (st)
        return fail(s, st == CB_ERR_NOMEM ? st : CB_ERR_PARSE, "face %d: %s", face, e.msg);
    return CB_OK;
}

/* Refuses a face of n != 3 vertices as the OpenMesh adapter does. */
static cb_status not_triangle(src *s, int face, long long n)
{
    if (n < 3)
        return fail(s, CB_ERR_PARSE, "face %d has %lld vertices", face, n);
    return fail(s, CB_ERR_UNSUPPORTED, "face %d has %lld vertices; only triangle meshes are read",
                face, n);
}

/* Room for the counts a header announces, but never more than a file of s->size bytes can
 * hold (min_vertex, min_face bytes each): a header that lies is caught when its data ends,
 * not by allocating what it claims. */
static cb_status reserve(src *s, long long nv, long long nf, int min_vertex, int min_face)
{
    long long v = nv < s->size / min_vertex + 1 ? nv : s->size / min_vertex + 1;
    long long f = nf < s->size / min_face + 1 ? nf : s->size / min_face + 1;
    cb_error e;
    if (cb_mesh_reserve(s->m, (int)v, (int)f, &e))
        return cb_error_set(s->err, CB_ERR_NOMEM, "%s: no memory for %lld vertices and %lld "
                            "triangles", s->path, v, f);
    return CB_OK;
}

/* ---------------------------------------------------------------- OFF ---------------------- */

/* OFF (Geomview): a keyword line [ST][C][N]OFF [BINARY]; the counts of vertices, faces and
 * edges (the last ignored, and optional when the line ends before it); per vertex x y z, then
 * nx ny nz for N, then the rest of the line (colour, texture coordinates) ignored; per face the
 * vertex count, the indices, and the rest of the line (a colour) ignored. '#' starts a comment.
 * BINARY is read as OpenMesh writes it: little-endian 32-bit counts, floats and indices, a
 * colour of three 32-bit integers per vertex for C, no face colour. */

typedef struct {
    int normals, colours, texcoords;
} off_layout;

static cb_status off_eof(src *s, const char *what, long long k, long long n)
{
    return fail(s, CB_ERR_PARSE, "unexpected end of file in %s %lld of the %lld the header "
                "announces", what, k, n);
}

static uint32_t le32(const unsigned char *b)
{
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

static float le_float(const unsigned char *b)
{
    uint32_t u = le32(b);
    float x;
    memcpy(&x, &u, sizeof x);
    return x;
}

static cb_status read_off_binary(src *s, const off_layout *lay)
{
    s->binary = 1;
    unsigned char b[16];
    if (!read_bytes(s, b, 12))
        return fail(s, CB_ERR_PARSE, "unexpected end of file in the counts");
    uint32_t nv = le32(b), nf = le32(b + 4);
    if (nv > INT_MAX || nf > INT_MAX)
        return fail(s, CB_ERR_PARSE, "%u vertices and %u faces: more than this reader holds",
                    nv, nf);
    cb_status st = reserve(s, nv, nf, 12, 16);
    size_t extra = 4 * (3 * (size_t)lay->normals + 3 * (size_t)lay->colours +
                        2 * (size_t)lay->texcoords);
    for (uint32_t i = 0; i < nv && !st; i++) {
        double p[3];
        if (!read_bytes(s, b, 12))
            return off_eof(s, "vertex", i, nv);
        for (int k = 0; k < 3; k++)
            p[k] = le_float(b + 4 * k);
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
            return fail(s, CB_ERR_PARSE, "vertex %u has a coordinate that is not a finite number",
                        i);
        for (size_t k = 0; k < extra; k++)
            if (src_get(s) < 0)
                return off_eof(s, "vertex", i, nv);
        cb_error e;
        if (cb_mesh_append_vertex(s->m, p, &e))
            return cb_error_set(s->err, CB_ERR_NOMEM, "%s: %s", s->path, e.msg);
    }
    for (uint32_t i = 0; i < nf && !st; i++) {
        if (!read_bytes(s, b, 4))
            return off_eof(s, "face", i, nf);
        uint32_t n = le32(b);
        if (n != 3)
            return not_triangle(s, (int)i, n);
        long long v[3];
        if (!read_bytes(s, b, 12))
            return off_eof(s, "face", i, nf);
        for (int k = 0; k < 3; k++)
            v[k] = le32(b + 4 * k) > INT_MAX ? -1 : (long long)le32(b + 4 * k);
        st = add_triangle(s, (int)i, v);
    }
    if (!st && src_peek(s) >= 0)
        return fail(s, CB_ERR_PARSE, "more data after the %u faces the header announces", nf);
    return st;
}

static cb_status read_off(src *s)
{
    char tok[TOKEN_MAX], buf[32];
    int r = next_token(s, tok, 1);
    if (r <= 0)
        return r < 0 ? s->err->status : cb_error_set(s->err, CB_ERR_PARSE, "%s: empty file",
                                                     s->path);
    /* The keyword: [ST][C][N][4][n]OFF, each prefix a flag. */
    off_layout lay;
    const char *p = tok;
    lay.texcoords = !strncmp(p, "ST", 2);
    p += 2 * lay.texcoords;
    lay.colours = *p == 'C';
    p += lay.colours;
    lay.normals = *p == 'N';
    p += lay.normals;
    int four = *p == '4';
    p += four;
    int n_dim = *p == 'n';
    p += n_dim;
    int high_dim = four || n_dim;
    /* A verdict on the whole file: no line number (tests/test_mesh_check.c expects "path: "). */
    if (strcmp(p, "OFF"))
        return cb_error_set(s->err, CB_ERR_PARSE, "%s: not an OFF file: it does not start with OFF",
                            s->path);
    if (high_dim)
        return fail(s, CB_ERR_UNSUPPORTED, "%s: only vertices of 3 coordinates are read",
                    shown(tok, buf));
    long header_line = s->tok_line;
    r = next_token(s, tok, 1);
    if (r < 0)
        return s->err->status;
    if (r > 0 && s->tok_line == header_line && !strcmp(tok, "BINARY")) {
        skip_line(s);
        return read_off_binary(s, &lay);
    }
    /* The counts: vertices, faces, and edges when the line holds a third number. */
    long long count[3] = {0, 0, 0};
    static const char *const names[3] = {"vertex count", "face count", "edge count"};
    long count_line = 0;
    for (int k = 0; k < 3; k++) {
        if (k > 0 && (r = next_token(s, tok, 1)) < 0)
            return s->err->status;
        if (r == 0)
            return fail(s, CB_ERR_PARSE, "unexpected end of file in the counts");
        if (k == 1)
            count_line = s->tok_line;
        if (k == 2 && s->tok_line != count_line) {
            push_back(s, tok);
            break;
        }
        long long most = k < 2 ? INT_MAX : LLONG_MAX;
        if (!parse_int(tok, 0, most, &count[k]))
            return fail(s, CB_ERR_PARSE, "%s '%s' is not a whole number in 0..%lld", names[k],
                        shown(tok, buf), most);
    }
    long long nv = count[0], nf = count[1];
    cb_status st = reserve(s, nv, nf, 6, 8);
    for (long long i = 0; i < nv && !st; i++) {
        double x[6];
        for (int k = 0; k < 3 + 3 * lay.normals; k++) {
            if ((r = next_token(s, tok, 1)) <= 0)
                return r < 0 ? s->err->status : off_eof(s, "vertex", i, nv);
            if (!parse_real(tok, &x[k]))
                return fail(s, CB_ERR_PARSE, "vertex %lld: %s %d is '%s', not a finite number",
                            i, k < 3 ? "coordinate" : "normal coordinate", k % 3 + 1,
                            shown(tok, buf));
        }
        skip_line(s);
        cb_error e;
        if (cb_mesh_append_vertex(s->m, x, &e))
            return cb_error_set(s->err, CB_ERR_NOMEM, "%s: %s", s->path, e.msg);
    }
    for (long long i = 0; i < nf && !st; i++) {
        long long n, v[3];
        if ((r = next_token(s, tok, 1)) <= 0)
            return r < 0 ? s->err->status : off_eof(s, "face", i, nf);
        if (!parse_int(tok, 0, INT_MAX, &n))
            return fail(s, CB_ERR_PARSE, "face %lld: vertex count '%s' is not a whole number",
                        i, shown(tok, buf));
        if (n != 3)
            return not_triangle(s, (int)i, n);
        for (int k = 0; k < 3; k++) {
            if ((r = next_token(s, tok, 1)) <= 0)
                return r < 0 ? s->err->status : off_eof(s, "face", i, nf);
            if (!parse_int(tok, 0, INT_MAX, &v[k]))
                return fail(s, CB_ERR_PARSE, "face %lld: vertex index '%s' is not a whole "
                            "number >= 0", i, shown(tok, buf));
        }
        skip_line(s);
        st = add_triangle(s, (int)i, v);
    }
    if (!st && (r = next_token(s, tok, 1)) != 0)
        return r < 0 ? s->err->status
                     : fail(s, CB_ERR_PARSE, "'%s' after the %lld faces the header announces",
                            shown(tok, buf), nf);
    return st;
}

/* ---------------------------------------------------------------- PLY ---------------------- */

/* PLY (Stanford): a header of lines, "ply", "format ascii|binary_little_endian|
 * binary_big_endian 1.0", elements with their counts and properties (scalars, and lists with a
 * count type), comments, "end_header"; then every element in order, each item's properties in
 * order, as text tokens or packed binary. Every element and property is read (lists included)
 * whatever it is; the vertex element's x, y, z and the face element's list vertex_indices (or
 * vertex_index) are kept. Values of a float property are rounded to float, as declared. */

enum { PLY_MAX_ELEMENTS = 32, PLY_MAX_PROPERTIES = 64 };

typedef enum {
    T_INT8,
    T_UINT8,
    T_INT16,
    T_UINT16,
    T_INT32,
    T_UINT32,
    T_FLOAT32,
    T_FLOAT64
} ply_type;

static const struct {
    const char *name, *alias;
    int size;
    long long lo, hi;
} PLY_TYPES[] = {{"char", "int8", 1, INT8_MIN, INT8_MAX},
                 {"uchar", "uint8", 1, 0, UINT8_MAX},
                 {"short", "int16", 2, INT16_MIN, INT16_MAX},
                 {"ushort", "uint16", 2, 0, UINT16_MAX},
                 {"int", "int32", 4, INT32_MIN, INT32_MAX},
                 {"uint", "uint32", 4, 0, UINT32_MAX},
                 {"float", "float32", 4, 0, 0},
                 {"double", "float64", 8, 0, 0}};

static int ply_type_of(const char *word)
{
    for (int t = 0; t < 8; t++)
        if (!strcmp(word, PLY_TYPES[t].name) || !strcmp(word, PLY_TYPES[t].alias))
            return t;
    return -1;
}

typedef struct {
    char name[64];
    int list;            /* a list: count_type, then that many values of type */
    ply_type count_type, type;
    int role;            /* 0..2: the vertex's x, y, z; 3: the face's vertex indices; -1 */
} ply_property;

typedef struct {
    char name[64];
    long long count;
    ply_property props[PLY_MAX_PROPERTIES];
    int n_props;
} ply_element;

typedef struct {
    int format; /* 0 ascii, 1 little-endian, 2 big-endian */
    ply_element el[PLY_MAX_ELEMENTS];
    int n_el;
    int vertex, face; /* the elements, or -1 */
} ply_header;

/* One header line into line (without its end or trailing blanks): 1, or 2 when the line was
 * longer and only its start is kept (harmless in a comment); 0 at the end of the file. */
static int header_line(src *s, char line[LINE_MAX_PLY])
{
    int c, n = 0, cut = 0;
    if (src_peek(s) < 0)
        return 0;
    s->tok_line = s->line;
    while ((c = src_get(s)) >= 0 && c != '\n') {
        if (n < LINE_MAX_PLY - 1)
            line[n++] = (char)c;
        else
            cut = 1;
    }
    while (n > 0 && is_space((unsigned char)line[n - 1]))
        n--;
    line[n] = '\0';
    return 1 + cut;
}

/* Splits line into at most max words; returns how many there are (counting beyond max). */
static int split_words(char *line, char *words[], int max)
{
    int n = 0;
    for (char *p = line;;) {
        while (*p && is_space((unsigned char)*p))
            p++;
        if (!*p)
            return n;
        if (n < max)
            words[n] = p;
        n++;
        while (*p && !is_space((unsigned char)*p))
            p++;
        if (*p)
            *p++ = '\0';
    }
}

static cb_status ply_read_header(src *s, ply_header *h)
{
    char line[LINE_MAX_PLY], buf[32];
    char *w[8];
    int r = header_line(s, line);
    if (r == 0)
        return cb_error_set(s->err, CB_ERR_PARSE, "%s: empty file", s->path);
    if (strcmp(line, "ply") && strcmp(line, "PLY"))
        return cb_error_set(s->err, CB_ERR_PARSE, "%s: not a PLY file: it does not start with ply",
                            s->path);
    h->format = -1;
    h->n_el = 0;
    h->vertex = h->face = -1;
    for (;;) {
        if ((r = header_line(s, line)) == 0)
            return fail(s, CB_ERR_PARSE, "the file ends inside the header, before end_header");
        int n = split_words(line, w, 8);
        if (n == 0)
            continue;
        if (!strcmp(w[0], "end_header") && n == 1)
            break;
        if (!strcmp(w[0], "comment") || !strcmp(w[0], "obj_info"))
            continue;
        if (r == 2)
            return fail(s, CB_ERR_PARSE, "header line longer than %d bytes", LINE_MAX_PLY - 1);
        if (!strcmp(w[0], "format")) {
            static const char *const formats[] = {"ascii", "binary_little_endian",
                                                  "binary_big_endian"};
            h->format = -1;
            for (int k = 0; k < 3 && n == 3; k++)
                if (!strcmp(w[1], formats[k]))
                    h->format = k;
            if (h->format < 0)
                return fail(s, CB_ERR_PARSE, "unknown format line (known: format ascii|"
                            "binary_little_endian|binary_big_endian 1.0)");
        } else if (!strcmp(w[0], "element")) {
            long long count;
            if (n != 3 || !parse_int(w[2], 0, INT_MAX, &count))
                return fail(s, CB_ERR_PARSE, "expected 'element NAME COUNT' (COUNT in 0..%d)",
                            INT_MAX);
            if (h->n_el == PLY_MAX_ELEMENTS)
                return fail(s, CB_ERR_UNSUPPORTED, "more than %d elements", PLY_MAX_ELEMENTS);
            ply_element *e = &h->el[h->n_el];
            snprintf(e->name, sizeof e->name, "%s", w[1]);
            e->count = count;
            e->n_props = 0;
            if (!strcmp(w[1], "vertex") && h->vertex < 0)
                h->vertex = h->n_el;
            if (!strcmp(w[1], "face") && h->face < 0)
                h->face = h->n_el;
            h->n_el++;
        } else if (!strcmp(w[0], "property")) {
            if (h->n_el == 0)
                return fail(s, CB_ERR_PARSE, "a property before any element");
            ply_element *e = &h->el[h->n_el - 1];
            if (e->n_props == PLY_MAX_PROPERTIES)
                return fail(s, CB_ERR_UNSUPPORTED, "element %s has more than %d properties",
                            e->name, PLY_MAX_PROPERTIES);
            ply_property *p = &e->props[e->n_props];
            p->role = -1;
            const char *name;
            if (n == 5 && !strcmp(w[1], "list")) {
                int ct = ply_type_of(w[2]), t = ply_type_of(w[3]);
                if (ct < 0 || t < 0 || ct >= T_FLOAT32)
                    return fail(s, CB_ERR_PARSE, "expected 'property list COUNT_TYPE TYPE NAME' "
                                "with an integer COUNT_TYPE");
                p->list = 1;
                p->count_type = (ply_type)ct;
                p->type = (ply_type)t;
                name = w[4];
            } else if (n == 3) {
                /* Some writers put the name first; a type is never a name. */
                int t = ply_type_of(w[1]), swapped = t < 0;
                if (swapped)
                    t = ply_type_of(w[2]);
                if (t < 0)
                    return fail(s, CB_ERR_PARSE, "expected 'property TYPE NAME' (types: char, "
                                "uchar, short, ushort, int, uint, float, double)");
                p->list = 0;
                p->count_type = p->type = (ply_type)t;
                name = swapped ? w[1] : w[2];
            } else {
                return fail(s, CB_ERR_PARSE, "expected 'property TYPE NAME' or 'property list "
                            "COUNT_TYPE TYPE NAME'");
            }
            snprintf(p->name, sizeof p->name, "%s", name);
            int is_vertex = h->n_el - 1 == h->vertex, is_face = h->n_el - 1 == h->face;
            for (int k = 0; k < 3 && is_vertex && !p->list; k++)
                if (!strcmp(name, (const char *[]){"x", "y", "z"}[k]))
                    p->role = k;
            if (is_face && p->list &&
                (!strcmp(name, "vertex_indices") || !strcmp(name, "vertex_index"))) {
                if (p->type >= T_FLOAT32)
                    return fail(s, CB_ERR_PARSE, "face vertex indices of type %s: they must be "
                                "integers", PLY_TYPES[p->type].name);
                p->role = 3;
            }
            e->n_props++;
        } else {
            return fail(s, CB_ERR_PARSE, "unknown header line starting '%s'", shown(w[0], buf));
        }
    }
    if (h->format < 0)
        return fail(s, CB_ERR_PARSE, "the header has no format line");
    /* What is kept must be there, once each. */
    if (h->vertex >= 0) {
        int have[4] = {0, 0, 0, 0};
        for (int k = 0; k < h->el[h->vertex].n_props; k++)
            if (h->el[h->vertex].props[k].role >= 0)
                have[h->el[h->vertex].props[k].role]++;
        for (int k = 0; k < 3; k++)
            if (have[k] != 1)
                return fail(s, CB_ERR_PARSE, "the vertex element has %d properties %s; one "
                            "is needed", have[k], (const char *[]){"x", "y", "z"}[k]);
    }
    if (h->face >= 0) {
        int have = 0;
        for (int k = 0; k < h->el[h->face].n_props; k++)
            have += h->el[h->face].props[k].role == 3;
        if (have != 1)
            return fail(s, CB_ERR_PARSE, "the face element has %d lists vertex_indices; one is "
                        "needed", have);
        if (h->el[h->face].count > 0 && h->vertex < 0)
            return fail(s, CB_ERR_PARSE, "faces but no vertex element");
    }
    return CB_OK;
}

/* Where a value is read, for messages: element item k (vertex 12, face 3, or NAME 5). */
typedef struct {
    const ply_element *e;
    long long item;
    const ply_property *p;
} ply_place;

static cb_status ply_bad(src *s, const ply_place *at, const char *what)
{
    return fail(s, CB_ERR_PARSE, "%s %lld: property %s: %s", at->e->name, at->item, at->p->name,
                what);
}

/* One value of type t, as an integer (*i, integer types) or a real (*x, all types). */
static cb_status ply_value(src *s, int format, ply_type t, const ply_place *at, long long *i,
                           double *x)
{
    char tok[TOKEN_MAX], buf[32], what[96];
    if (format == 0) {
        int r = next_token(s, tok, 0);
        if (r <= 0)
            return r < 0 ? s->err->status
                         : fail(s, CB_ERR_PARSE, "unexpected end of file in %s %lld of the %lld "
                                "the header announces", at->e->name, at->item, at->e->count);
        if (t < T_FLOAT32) {
            if (!parse_int(tok, PLY_TYPES[t].lo, PLY_TYPES[t].hi, i)) {
                snprintf(what, sizeof what, "'%s' is not a whole number of type %s",
                         shown(tok, buf), PLY_TYPES[t].name);
                return ply_bad(s, at, what);
            }
            *x = (double)*i;
            return CB_OK;
        }
        if (!parse_real(tok, x) || (t == T_FLOAT32 && !isfinite((float)*x))) {
            snprintf(what, sizeof what, "'%s' is not a finite number of type %s",
                     shown(tok, buf), PLY_TYPES[t].name);
            return ply_bad(s, at, what);
        }
        if (t == T_FLOAT32)
            *x = (float)*x;
        return CB_OK;
    }
    unsigned char b[8];
    int size = PLY_TYPES[t].size;
    if (!read_bytes(s, b, (size_t)size))
        return fail(s, CB_ERR_PARSE, "unexpected end of file in %s %lld of the %lld the header "
                    "announces", at->e->name, at->item, at->e->count);
    uint64_t u = 0;
    for (int k = 0; k < size; k++)
        u |= (uint64_t)b[format == 1 ? k : size - 1 - k] << (8 * k);
    switch (t) {
    case T_INT8: *i = (int8_t)u; break;
    case T_UINT8: *i = (uint8_t)u; break;
    case T_INT16: *i = (int16_t)u; break;
    case T_UINT16: *i = (uint16_t)u; break;
    case T_INT32: *i = (int32_t)u; break;
    case T_UINT32: *i = (uint32_t)u; break;
    case T_FLOAT32: {
        uint32_t u32 = (uint32_t)u;
        float f;
        memcpy(&f, &u32, sizeof f);
        *x = f;
        return CB_OK;
    }
    case T_FLOAT64: memcpy(x, &u, sizeof *x); return CB_OK;
    }
    *x = (double)*i;
    return CB_OK;
}

/* The data after the header h: every element in order, x, y, z and the vertex indices kept. */
static cb_status read_ply_data(src *s, const ply_header *h)
{
    cb_status st;
    s->binary = h->format != 0;
    /* Least bytes an item takes: a digit and a separator per text value, the packed sizes in
     * binary (a list at least its count); more items than the file can hold is a lie of the
     * header, refused before anything is allocated for them. */
    long long left = s->size - src_offset(s), need = 0;
    for (int k = 0; k < h->n_el; k++) {
        long long per = 0;
        for (int j = 0; j < h->el[k].n_props; j++) {
            const ply_property *p = &h->el[k].props[j];
            per += h->format == 0 ? 2 : PLY_TYPES[p->list ? p->count_type : p->type].size;
        }
        if (per > 0 && h->el[k].count > (left - need) / per + 1)
            return fail(s, CB_ERR_PARSE, "the header announces %lld items of element %s; the "
                        "%lld bytes after it cannot hold them",
                        h->el[k].count, h->el[k].name, left);
        need += per * h->el[k].count;
    }
    long long nv = h->vertex >= 0 ? h->el[h->vertex].count : 0;
    long long nf = h->face >= 0 ? h->el[h->face].count : 0;
    if ((st = reserve(s, nv, nf, 1, 1)))
        return st;
    /* The vertices exist from the start (at the origin until read), so that faces can be
     * checked against them even when the face element comes first. */
    const double origin[3] = {0, 0, 0};
    for (long long k = 0; k < nv; k++)
        if (cb_mesh_append_vertex(s->m, origin, NULL))
            return cb_error_set(s->err, CB_ERR_NOMEM, "%s: no memory for %lld vertices", s->path,
                                nv);
    for (int k = 0; k < h->n_el && !st; k++) {
        const ply_element *e = &h->el[k];
        ply_place at = {e, 0, NULL};
        for (at.item = 0; at.item < e->count && !st; at.item++)
            for (int j = 0; j < e->n_props && !st; j++) {
                const ply_property *p = &e->props[j];
                at.p = p;
                long long n = 1, iv = 0, tri[3] = {-1, -1, -1};
                double x = 0;
                if (p->list) {
                    if ((st = ply_value(s, h->format, p->count_type, &at, &n, &x)))
                        break;
                    if (n < 0)
                        st = ply_bad(s, &at, "a list of negative length");
                    else if (p->role == 3 && n != 3)
                        st = not_triangle(s, (int)at.item, n);
                }
                for (long long v = 0; v < n && !st; v++) {
                    if ((st = ply_value(s, h->format, p->type, &at, &iv, &x)))
                        break;
                    if (p->role >= 0 && p->role < 3) {
                        if (!isfinite(x))
                            st = ply_bad(s, &at, "not a finite number");
                        else
                            s->m->xyz[3 * at.item + p->role] = x;
                    } else if (p->role == 3) {
                        tri[v] = iv < 0 || iv > INT_MAX ? -1 : iv;
                    }
                }
                if (!st && p->role == 3)
                    st = add_triangle(s, (int)at.item, tri);
            }
    }
    if (st)
        return st;
    if (h->format == 0) {
        char tok[TOKEN_MAX], buf[32];
        int r = next_token(s, tok, 0);
        if (r != 0)
            return r < 0 ? s->err->status
                         : fail(s, CB_ERR_PARSE, "'%s' after the elements the header announces",
                                shown(tok, buf));
    } else if (src_peek(s) >= 0) {
        return fail(s, CB_ERR_PARSE, "more data after the elements the header announces");
    }
    return CB_OK;
}


static cb_status read_ply(src *s)
{
    /* The header is large (elements times properties): not on the stack. */
    ply_header *h = malloc(sizeof *h);
    if (!h)
        return cb_error_set(s->err, CB_ERR_NOMEM, "%s: out of memory", s->path);
    cb_status st = ply_read_header(s, h);
    if (!st)
        st = read_ply_data(s, h);
    free(h);
    return st;
}

/* ---------------------------------------------------------------- reading ------------------ */

cb_status cb_mesh_read(cb_mesh_t mesh, const char *path, cb_error *err)
{
    cb_error local;
    if (!err)
        err = &local;
    cb_mesh_clear(mesh);
    cb_mesh_format fmt;
    cb_status st = cb_mesh_format_of_path(&fmt, path, err);
    if (st)
        return st;
    /* Only regular files are read, and that is asked before opening: fopen opens a directory
     * (OpenMesh's STL reader then loops for ever on it), and opening a FIFO blocks. */
    struct stat sb;
    if (stat(path, &sb))
        return cb_error_set(err, CB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (!S_ISREG(sb.st_mode))
        return cb_error_set(err, CB_ERR_IO, "%s: %s", path,
                            S_ISDIR(sb.st_mode) ? "is a directory" : "not a regular file");
    FILE *f = fopen(path, "rb");
    if (!f)
        return cb_error_set(err, CB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (fmt == CB_MESH_OFF || fmt == CB_MESH_PLY) {
        src *s = calloc(1, sizeof *s);
        if (!s) {
            fclose(f);
            return cb_error_set(err, CB_ERR_NOMEM, "%s: out of memory", path);
        }
        s->line = s->tok_line = 1;
        s->f = f;
        s->path = path;
        s->size = (long long)sb.st_size;
        s->err = err;
        s->m = mesh;
        st = fmt == CB_MESH_OFF ? read_off(s) : read_ply(s);
        if (!st && s->read_error)
            st = fail(s, CB_ERR_IO, "read error");
        free(s);
        fclose(f);
    } else {
        fclose(f);
        st = cb_mesh_openmesh_read(mesh, path, err);
    }
    if (!st && mesh->n_triangles == 0)
        st = cb_error_set(err, CB_ERR_PARSE, "%s: no triangles read", path);
    if (st)
        cb_mesh_clear(mesh);
    return st;
}
