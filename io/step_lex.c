/* ISO 10303-21 tokenizer and parser: one pass over the buffer, building the node, part and
 * record arrays of step_internal.h. Recursion is bounded by MAX_DEPTH list nesting. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "io/step_internal.h"

enum { MAX_DEPTH = 64, MAX_NUMBER_LEN = 64 };

typedef struct {
    step_file *f;
    const char *s;
    size_t pos, len;
    int line;
    long id; /* entity being read, 0 outside one */
    int id_line;
    int name_off, name_len; /* its (first) type name, for messages */
} lexer;

/* "path:line: [#id NAME: ]message". */
static cb_status lex_fail(const lexer *lx, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static cb_status lex_fail(const lexer *lx, int line, const char *fmt, ...)
{
    char msg[CB_ERROR_MSG_LEN];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (lx->id && lx->name_len)
        return cb_error_set(lx->f->err, CB_ERR_PARSE, "%s:%d: #%ld %.*s: %s", lx->f->path, line,
                            lx->id, lx->name_len > 64 ? 64 : lx->name_len, lx->s + lx->name_off,
                            msg);
    if (lx->id)
        return cb_error_set(lx->f->err, CB_ERR_PARSE, "%s:%d: #%ld: %s", lx->f->path, line, lx->id,
                            msg);
    return cb_error_set(lx->f->err, CB_ERR_PARSE, "%s:%d: %s", lx->f->path, line, msg);
}

/* Grows *arr (of *cap elements of size sz) to hold at least need. */
static int grow(void **arr, int *cap, int need, size_t sz)
{
    if (need <= *cap)
        return 1;
    if (need > (1 << 29))
        return 0;
    int c = *cap ? *cap : 256;
    while (c < need)
        c *= 2;
    void *p = realloc(*arr, (size_t)c * sz);
    if (!p)
        return 0;
    *arr = p;
    *cap = c;
    return 1;
}

static int is_alpha(int c) { return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || c == '_'; }
static int is_digit(int c) { return c >= '0' && c <= '9'; }

static int peek(const lexer *lx) { return lx->pos < lx->len ? (unsigned char)lx->s[lx->pos] : -1; }

/* Skips white space and comments. */
static cb_status skip_space(lexer *lx)
{
    while (lx->pos < lx->len) {
        char c = lx->s[lx->pos];
        if (c == '\n') {
            lx->line++;
            lx->pos++;
        } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
            lx->pos++;
        } else if (c == '/' && lx->pos + 1 < lx->len && lx->s[lx->pos + 1] == '*') {
            int start = lx->line;
            lx->pos += 2;
            for (;;) {
                if (lx->pos + 1 >= lx->len)
                    return lex_fail(lx, start, "unterminated comment");
                if (lx->s[lx->pos] == '\n')
                    lx->line++;
                if (lx->s[lx->pos] == '*' && lx->s[lx->pos + 1] == '/')
                    break;
                lx->pos++;
            }
            lx->pos += 2;
        } else {
            break;
        }
    }
    return CB_OK;
}

/* Describes the byte at the cursor for a message. */
static const char *describe(const lexer *lx, char buf[32])
{
    int c = peek(lx);
    if (c < 0)
        return "end of file";
    if (c >= 0x20 && c < 0x7f)
        snprintf(buf, 32, "'%c'", c);
    else
        snprintf(buf, 32, "byte 0x%02x", c);
    return buf;
}

static cb_status expect_char(lexer *lx, char want, const char *context)
{
    cb_status st = skip_space(lx);
    if (st)
        return st;
    if (peek(lx) != (unsigned char)want) {
        char buf[32];
        return lex_fail(lx, lx->line, "expected '%c' %s, found %s", want, context,
                        describe(lx, buf));
    }
    lx->pos++;
    return CB_OK;
}

/* Upper-cases n bytes of the buffer at off: ISO 10303-21 writes keywords and enumerations in
 * upper case, but writers exist that do not (`Header;`, `EndSec;`), and every later comparison
 * (entity types, unit names, enumerations) is then made in one case. */
static void to_upper(lexer *lx, size_t off, size_t n)
{
    char *s = lx->f->buf + off;
    for (size_t k = 0; k < n; k++)
        if (s[k] >= 'a' && s[k] <= 'z')
            s[k] = (char)(s[k] - 'a' + 'A');
}

/* A keyword [A-Za-z_][A-Za-z0-9_-]* at the cursor, upper-cased; *len 0 when there is none. */
static void keyword(lexer *lx, int *off, int *len)
{
    size_t p = lx->pos;
    if (p < lx->len && is_alpha((unsigned char)lx->s[p])) {
        while (p < lx->len && (is_alpha((unsigned char)lx->s[p]) ||
                               is_digit((unsigned char)lx->s[p]) || lx->s[p] == '-'))
            p++;
    }
    to_upper(lx, lx->pos, p - lx->pos);
    *off = (int)lx->pos;
    *len = (int)(p - lx->pos);
    lx->pos = p;
}

static int keyword_is(const lexer *lx, int off, int len, const char *word)
{
    return len == (int)strlen(word) && !memcmp(lx->s + off, word, (size_t)len);
}

static int new_node(lexer *lx, step_kind kind)
{
    step_file *f = lx->f;
    if (!grow((void **)&f->nodes, &f->cap_nodes, f->n_nodes + 1, sizeof *f->nodes))
        return -1;
    step_node *x = &f->nodes[f->n_nodes];
    memset(x, 0, sizeof *x);
    x->kind = (unsigned char)kind;
    x->line = lx->line;
    x->span = 1;
    return f->n_nodes++;
}

static cb_status no_memory(const lexer *lx)
{
    return cb_error_set(lx->f->err, CB_ERR_NOMEM, "%s:%d: out of memory", lx->f->path, lx->line);
}

/* A number: [+-] digits [. digits] [E [+-] digits]; REAL when it has a point or exponent. */
static cb_status number(lexer *lx)
{
    size_t p = lx->pos, start = p;
    int digits = 0, real = 0;
    if (p < lx->len && (lx->s[p] == '+' || lx->s[p] == '-'))
        p++;
    while (p < lx->len && is_digit((unsigned char)lx->s[p]))
        p++, digits++;
    if (p < lx->len && lx->s[p] == '.') {
        real = 1;
        p++;
        while (p < lx->len && is_digit((unsigned char)lx->s[p]))
            p++, digits++;
    }
    if (digits && p < lx->len && (lx->s[p] == 'E' || lx->s[p] == 'e')) {
        size_t q = p + 1;
        if (q < lx->len && (lx->s[q] == '+' || lx->s[q] == '-'))
            q++;
        if (q < lx->len && is_digit((unsigned char)lx->s[q])) {
            while (q < lx->len && is_digit((unsigned char)lx->s[q]))
                q++;
            p = q;
            real = 1;
        }
    }
    if (!digits)
        return lex_fail(lx, lx->line, "malformed number '%.*s'", (int)(p - start + 1),
                        lx->s + start);
    if (p - start >= MAX_NUMBER_LEN)
        return lex_fail(lx, lx->line, "number of %zu characters", p - start);
    char tmp[MAX_NUMBER_LEN];
    memcpy(tmp, lx->s + start, p - start);
    tmp[p - start] = '\0';
    int k = new_node(lx, real ? STEP_REAL : STEP_INT);
    if (k < 0)
        return no_memory(lx);
    step_node *x = &lx->f->nodes[k];
    x->v.real = strtod(tmp, NULL);
    if (!isfinite(x->v.real))
        return lex_fail(lx, lx->line, "number %s is not a finite double", tmp);
    if (!real) {
        if (fabs(x->v.real) > 9e15)
            return lex_fail(lx, lx->line, "integer %s out of range", tmp);
        x->ival = strtol(tmp, NULL, 10);
    }
    lx->pos = p;
    return CB_OK;
}

/* Text between delimiters: 'string' ('' is a quote), "binary", .ENUM. */
static cb_status delimited(lexer *lx, step_kind kind, char close)
{
    int start_line = lx->line;
    size_t p = ++lx->pos;
    for (;;) {
        if (p >= lx->len)
            return lex_fail(lx, start_line, "unterminated %s",
                            kind == STEP_STRING ? "string"
                            : kind == STEP_ENUM ? "enumeration"
                                                : "binary");
        char c = lx->s[p];
        /* \S\c is the character c + 128 (ISO 10303-21 7.3.3): c may be a quote. */
        if (kind == STEP_STRING && c == '\\' && p + 3 < lx->len && lx->s[p + 1] == 'S' &&
            lx->s[p + 2] == '\\' && lx->s[p + 3] != '\n') {
            p += 4;
            continue;
        }
        if (c == '\n') {
            if (kind != STEP_STRING)
                return lex_fail(lx, start_line, "unterminated %s",
                                kind == STEP_ENUM ? "enumeration" : "binary");
            lx->line++;
        }
        if (c == close) {
            if (kind == STEP_STRING && p + 1 < lx->len && lx->s[p + 1] == '\'') {
                p += 2;
                continue;
            }
            /* A string is a parameter: its closing quote is followed by ',' or ')'. A lone
             * quote followed by anything else (not allowed, but written: bug28454's
             * directives) is taken as part of the text, as Open CASCADE reads it. */
            size_t q = p + 1;
            while (kind == STEP_STRING && q < lx->len &&
                   (lx->s[q] == ' ' || lx->s[q] == '\t' || lx->s[q] == '\r' || lx->s[q] == '\n'))
                q++;
            if (kind == STEP_STRING && q < lx->len && lx->s[q] != ',' && lx->s[q] != ')') {
                p++;
                continue;
            }
            break;
        }
        if (kind == STEP_ENUM && !is_alpha((unsigned char)c) && !is_digit((unsigned char)c))
            return lex_fail(lx, start_line, "malformed enumeration");
        p++;
    }
    int k = new_node(lx, kind);
    if (k < 0)
        return no_memory(lx);
    if (kind == STEP_ENUM)
        to_upper(lx, lx->pos, p - lx->pos);
    step_node *x = &lx->f->nodes[k];
    x->line = start_line;
    x->v.text.off = (int)lx->pos;
    x->v.text.len = (int)(p - lx->pos);
    lx->pos = p + 1;
    return CB_OK;
}

static cb_status param_list(lexer *lx, int node, int depth);

/* One parameter at the cursor. */
static cb_status param(lexer *lx, int depth)
{
    cb_status st = skip_space(lx);
    if (st)
        return st;
    int c = peek(lx), k;
    if (c == '(') {
        if ((k = new_node(lx, STEP_LIST)) < 0)
            return no_memory(lx);
        return param_list(lx, k, depth + 1);
    }
    if (c == '\'')
        return delimited(lx, STEP_STRING, '\'');
    if (c == '"')
        return delimited(lx, STEP_BINARY, '"');
    if (c == '.' && lx->pos + 1 < lx->len && is_alpha((unsigned char)lx->s[lx->pos + 1]))
        return delimited(lx, STEP_ENUM, '.');
    if (c == '+' || c == '-' || c == '.' || (c >= 0 && is_digit(c)))
        return number(lx);
    if (c == '$' || c == '*') {
        if (new_node(lx, c == '$' ? STEP_UNSET : STEP_DERIVED) < 0)
            return no_memory(lx);
        lx->pos++;
        return CB_OK;
    }
    if (c == '#') {
        size_t p = lx->pos + 1, start = p;
        long id = 0;
        while (p < lx->len && is_digit((unsigned char)lx->s[p]) && p - start < 16)
            id = id * 10 + (lx->s[p++] - '0');
        if (p == start || (p < lx->len && is_digit((unsigned char)lx->s[p])))
            return lex_fail(lx, lx->line, "malformed reference");
        if ((k = new_node(lx, STEP_REF)) < 0)
            return no_memory(lx);
        lx->f->nodes[k].v.ref = id;
        lx->pos = p;
        return CB_OK;
    }
    if (c >= 0 && is_alpha(c)) {
        int off, len;
        if ((k = new_node(lx, STEP_TYPED)) < 0)
            return no_memory(lx);
        keyword(lx, &off, &len);
        lx->f->nodes[k].v.text.off = off;
        lx->f->nodes[k].v.text.len = len;
        if ((st = expect_char(lx, '(', "after a typed parameter name")))
            return st;
        lx->pos--;
        return param_list(lx, k, depth + 1);
    }
    char buf[32];
    return lex_fail(lx, lx->line, "unexpected %s in a parameter list", describe(lx, buf));
}

/* The list whose '(' is at the cursor; its elements become the children of node. */
static cb_status param_list(lexer *lx, int node, int depth)
{
    if (depth > MAX_DEPTH)
        return lex_fail(lx, lx->line, "lists nested deeper than %d", MAX_DEPTH);
    lx->pos++; /* '(' */
    cb_status st = skip_space(lx);
    if (st)
        return st;
    int n = 0;
    if (peek(lx) == ')') {
        lx->pos++;
    } else {
        for (;;) {
            if ((st = param(lx, depth)))
                return st;
            n++;
            if ((st = skip_space(lx)))
                return st;
            int c = peek(lx);
            lx->pos++;
            if (c == ')')
                break;
            if (c != ',') {
                lx->pos--;
                char buf[32];
                return lex_fail(lx, lx->line, "expected ',' or ')' in a parameter list, found %s",
                                describe(lx, buf));
            }
        }
    }
    step_node *x = &lx->f->nodes[node];
    x->n = n;
    x->span = lx->f->n_nodes - node;
    return CB_OK;
}

/* NAME(params) at the cursor, appended as a part of the current record. */
static cb_status entity_part(lexer *lx, int record)
{
    step_file *f = lx->f;
    int off, len;
    keyword(lx, &off, &len);
    if (!len) {
        char buf[32];
        return lex_fail(lx, lx->line, "expected an entity name, found %s", describe(lx, buf));
    }
    if (!lx->name_len) {
        lx->name_off = off;
        lx->name_len = len;
    }
    cb_status st = skip_space(lx);
    if (st)
        return st;
    if (peek(lx) != '(')
        return lex_fail(lx, lx->line, "expected '(' after the entity name %.*s",
                        len > 64 ? 64 : len, lx->s + off);
    int k = new_node(lx, STEP_LIST);
    if (k < 0 || !grow((void **)&f->parts, &f->cap_parts, f->n_parts + 1, sizeof *f->parts))
        return no_memory(lx);
    if ((st = param_list(lx, k, 1)))
        return st;
    step_part *p = &f->parts[f->n_parts++];
    p->type = (int)step_type_lookup(lx->s + off, len);
    p->name_off = off;
    p->name_len = len;
    p->args = k;
    if (record >= 0)
        f->recs[record].n_parts++;
    return CB_OK;
}

/* #id = NAME(...); or #id = (A(...) B(...)); at the cursor. */
static cb_status entity_instance(lexer *lx)
{
    step_file *f = lx->f;
    size_t p = lx->pos + 1, start = p;
    long id = 0;
    while (p < lx->len && is_digit((unsigned char)lx->s[p]) && p - start < 16)
        id = id * 10 + (lx->s[p++] - '0');
    if (p == start || id <= 0 || (p < lx->len && is_digit((unsigned char)lx->s[p])))
        return lex_fail(lx, lx->line, "malformed entity instance name");
    lx->pos = p;
    lx->id = id;
    lx->id_line = lx->line;
    lx->name_len = 0;
    cb_status st = expect_char(lx, '=', "after the instance name");
    if (st)
        return st;
    if (!grow((void **)&f->recs, &f->cap_recs, f->n_recs + 1, sizeof *f->recs))
        return no_memory(lx);
    int rec = f->n_recs++;
    f->recs[rec] = (step_rec){.id = id, .line = lx->id_line, .part0 = f->n_parts};
    if ((st = skip_space(lx)))
        return st;
    if (peek(lx) == '(') {
        f->recs[rec].complex = 1;
        lx->pos++;
        for (;;) {
            if ((st = skip_space(lx)))
                return st;
            if (peek(lx) == ')')
                break;
            if ((st = entity_part(lx, rec)))
                return st;
        }
        lx->pos++;
        if (!f->recs[rec].n_parts)
            return lex_fail(lx, lx->line, "complex entity instance without parts");
    } else if ((st = entity_part(lx, rec))) {
        return st;
    }
    if ((st = expect_char(lx, ';', "at the end of the entity instance")))
        return st;
    lx->id = 0;
    return CB_OK;
}

/* Expects KEYWORD ; at the cursor. */
static cb_status statement(lexer *lx, const char *word)
{
    cb_status st = skip_space(lx);
    if (st)
        return st;
    int off, len;
    keyword(lx, &off, &len);
    if (!keyword_is(lx, off, len, word)) {
        if (!len && lx->pos >= lx->len)
            return lex_fail(lx, lx->line, "end of file, expected %s", word);
        return lex_fail(lx, lx->line, "expected %s, found '%.*s'", word,
                        len ? (len > 40 ? 40 : len) : 1,
                        len                 ? lx->s + off
                        : lx->pos < lx->len ? lx->s + lx->pos
                                            : "?");
    }
    return expect_char(lx, ';', word);
}

/* Header entities: parsed for syntax, then dropped. */
static cb_status header_section(lexer *lx)
{
    cb_status st = statement(lx, "HEADER");
    while (!st) {
        if ((st = skip_space(lx)))
            break;
        int save = lx->f->n_nodes, saved_parts = lx->f->n_parts;
        size_t pos = lx->pos;
        int off, len;
        keyword(lx, &off, &len);
        if (keyword_is(lx, off, len, "ENDSEC"))
            return expect_char(lx, ';', "ENDSEC");
        lx->pos = pos;
        if (lx->pos >= lx->len)
            return lex_fail(lx, lx->line, "end of file in the HEADER section");
        if ((st = entity_part(lx, -1)) || (st = expect_char(lx, ';', "after a header entity")))
            break;
        lx->f->n_nodes = save;
        lx->f->n_parts = saved_parts;
        lx->name_len = 0;
    }
    return st;
}

/* DATA; (or DATA(...);) then instances up to ENDSEC;. */
static cb_status data_section(lexer *lx)
{
    int data_line = lx->line;
    cb_status st = skip_space(lx);
    if (st)
        return st;
    if (peek(lx) == '(') {
        int save = lx->f->n_nodes, k = new_node(lx, STEP_LIST);
        if (k < 0)
            return no_memory(lx);
        if ((st = param_list(lx, k, 1)))
            return st;
        lx->f->n_nodes = save;
    }
    if ((st = expect_char(lx, ';', "after DATA")))
        return st;
    for (;;) {
        if ((st = skip_space(lx)))
            return st;
        int c = peek(lx);
        if (c == '#') {
            if ((st = entity_instance(lx)))
                return st;
            continue;
        }
        if (c < 0)
            return lex_fail(lx, lx->line,
                            "end of file in the DATA section opened at line %d (truncated?)",
                            data_line);
        int off, len;
        keyword(lx, &off, &len);
        if (keyword_is(lx, off, len, "ENDSEC"))
            return expect_char(lx, ';', "ENDSEC");
        char buf[32];
        if (!len)
            return lex_fail(lx, lx->line, "expected an entity instance '#id = ...', found %s",
                            describe(lx, buf));
        return lex_fail(lx, lx->line, "expected an entity instance '#id = ...', found '%.*s'",
                        len > 40 ? 40 : len, lx->s + off);
    }
}

static int rec_cmp(const void *a, const void *b)
{
    long x = ((const step_rec *)a)->id, y = ((const step_rec *)b)->id;
    return (x > y) - (x < y);
}

cb_status step_parse(step_file *f)
{
    lexer lx = {.f = f, .s = f->buf, .len = f->len, .line = 1};
    cb_status st = skip_space(&lx);
    if (st)
        return st;
    if (lx.pos >= lx.len)
        return cb_error_set(f->err, CB_ERR_PARSE, "%s: empty file", f->path);
    int off, len;
    keyword(&lx, &off, &len);
    if (!keyword_is(&lx, off, len, "ISO-10303-21"))
        return lex_fail(&lx, lx.line, "not a STEP file: it does not start with ISO-10303-21;");
    if ((st = expect_char(&lx, ';', "after ISO-10303-21")) || (st = header_section(&lx)))
        return st;
    int sections = 0;
    for (;;) {
        if ((st = skip_space(&lx)))
            return st;
        keyword(&lx, &off, &len);
        if (keyword_is(&lx, off, len, "DATA")) {
            if ((st = data_section(&lx)))
                return st;
            sections++;
            continue;
        }
        if (keyword_is(&lx, off, len, "END-ISO-10303-21") && sections) {
            if ((st = expect_char(&lx, ';', "END-ISO-10303-21")))
                return st;
            break;
        }
        if (!len && lx.pos >= lx.len)
            return lex_fail(&lx, lx.line, "end of file, expected %s (truncated?)",
                            sections ? "END-ISO-10303-21;" : "DATA;");
        return lex_fail(&lx, lx.line, "expected %s",
                        sections ? "DATA or END-ISO-10303-21" : "DATA");
    }
    /* Writers emit increasing ids; sort only when one did not. */
    int sorted = 1;
    for (int k = 1; k < f->n_recs && sorted; k++)
        sorted = f->recs[k - 1].id < f->recs[k].id;
    if (!sorted)
        qsort(f->recs, (size_t)f->n_recs, sizeof *f->recs, rec_cmp);
    for (int k = 1; k < f->n_recs; k++)
        if (f->recs[k - 1].id == f->recs[k].id) {
            const step_rec *a = &f->recs[k - 1], *b = &f->recs[k];
            if (a->line > b->line) {
                const step_rec *t = a;
                a = b;
                b = t;
            }
            return cb_error_set(f->err, CB_ERR_PARSE,
                                "%s:%d: #%ld: instance name used again (first at line %d)", f->path,
                                b->line, b->id, a->line);
        }
    return CB_OK;
}
