/* A robot controller loop on lplace's C API.
 *
 *   controller MAP RULES STREAM.csv
 *
 * Loads the engine once, resolves every percept column of the stream to a slot once, then per
 * frame: clear, set the percepts seen, step, act on the decision. Here "acting" is printing
 * one line per frame in the columns of `lplace eval --format csv` less `t` and `truth`:
 *
 *   line,outcome,place,necessity,reason,inconsistency
 *
 * so that `.ci/run` can compare this program's decisions with the CLI's, frame by frame.
 *
 * The input is lplace's CSV percept stream (ARCHITECTURE.md): a header row, then one frame per
 * row; `deg:NAME(ARG ARG)` / `val:NAME(ARG ARG)` columns hold a percept's degree and measured
 * value, an empty cell = not perceived. `lplace-c`'s example `stream_to_csv` writes it from
 * the JSON Lines form. Other columns (time, odometry, truth) are ignored: this controller uses
 * the engine frame by frame, without tracking.
 *
 * Build (see .ci/run): cc -std=c11 -Iinclude examples/c/controller.c \
 *     target/release/liblplace_c.a -lpthread -ldl -lm -o controller
 */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "lplace.h"

enum { COL_IGNORED = 0, COL_DEGREE = 1, COL_VALUE = 2 };

typedef struct {
    int kind;
    int slot;
} Column;

/* Splits `line` in place at commas (and the trailing newline); returns the number of cells. */
static size_t split(char *line, char **cells, size_t max_cells) {
    size_t n = 0;
    char *p = line;
    line[strcspn(line, "\r\n")] = '\0';
    while (n < max_cells) {
        cells[n++] = p;
        char *comma = strchr(p, ',');
        if (!comma) break;
        *comma = '\0';
        p = comma + 1;
    }
    return n;
}

/* Resolves a `deg:NAME(ARG ARG)` / `val:NAME` header cell to a column. Modifies `cell`. */
static Column column_of(const LplaceEngine *e, char *cell) {
    Column c = {COL_IGNORED, -1};
    if (strncmp(cell, "deg:", 4) == 0) {
        c.kind = COL_DEGREE;
    } else if (strncmp(cell, "val:", 4) == 0) {
        c.kind = COL_VALUE;
    } else {
        return c;
    }
    char *name = cell + 4;
    const char *args[16];
    size_t n_args = 0;
    char *open = strchr(name, '(');
    if (open) {
        *open = '\0';
        char *close = strchr(open + 1, ')');
        if (close) *close = '\0';
        for (char *a = strtok(open + 1, " "); a && n_args < 16; a = strtok(NULL, " ")) {
            args[n_args++] = a;
        }
    }
    c.slot = lplace_engine_slot(e, name, args, n_args);
    if (c.slot < 0) {
        fprintf(stderr, "controller: column %s: no such percept (code %d), ignored\n", name, c.slot);
        c.kind = COL_IGNORED;
    }
    return c;
}

/* A degree with 4 decimals, rounded as `lplace eval` does (half away from zero). */
static void print_degree(double x) {
    double c = x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
    unsigned v = (unsigned)round(c * 10000.0);
    printf("%u.%04u", v / 10000, v % 10000);
}

/* The library reports misuse instead of crashing; check a few of those promises first. */
static int check_contract(LplaceEngine *e) {
    LplaceDecision d;
    int ok = lplace_engine_set(e, -7, 0.5, NAN) == LPLACE_ERR_SLOT &&
             lplace_engine_set(e, (int)lplace_engine_slot_count(e), 0.5, NAN) == LPLACE_ERR_SLOT &&
             lplace_engine_set(NULL, 0, 0.5, NAN) == LPLACE_ERR_NULL &&
             lplace_engine_step(e, NULL) == LPLACE_ERR_NULL &&
             lplace_engine_step(NULL, &d) == LPLACE_ERR_NULL &&
             lplace_engine_slot(e, "no_such_percept", NULL, 0) == LPLACE_SLOT_UNKNOWN &&
             lplace_engine_slot(e, NULL, NULL, 0) == LPLACE_ERR_NULL &&
             lplace_engine_place_name(e, lplace_engine_place_count(e)) == NULL;
    if (!ok) fprintf(stderr, "controller: the library broke its contract\n");
    return ok;
}

/* Steps the engine on every row of `in`, printing one decision per frame. Returns 0 on success. */
static int run(LplaceEngine *e, FILE *in) {
    char *line = NULL;
    size_t cap = 0;
    size_t n_slots = lplace_engine_slot_count(e);
    /* Everything the loop needs is allocated here, once. */
    size_t max_cells = 4096;
    char **cells = malloc(max_cells * sizeof *cells);
    Column *cols = calloc(max_cells, sizeof *cols);
    double *degree = malloc((n_slots + 1) * sizeof *degree);
    double *value = malloc((n_slots + 1) * sizeof *value);
    int status = 1;
    if (!cells || !cols || !degree || !value) goto done;
    if (getline(&line, &cap, in) < 0) {
        fprintf(stderr, "controller: the stream has no header row\n");
        goto done;
    }
    size_t n_cols = split(line, cells, max_cells);
    for (size_t i = 0; i < n_cols; i++) cols[i] = column_of(e, cells[i]);

    puts("line,outcome,place,necessity,reason,inconsistency");
    unsigned long row = 0;
    while (getline(&line, &cap, in) >= 0) {
        row++;
        size_t n = split(line, cells, max_cells);
        for (size_t s = 0; s < n_slots; s++) degree[s] = NAN, value[s] = NAN;
        for (size_t i = 0; i < n && i < n_cols; i++) {
            if (cols[i].kind == COL_IGNORED || cells[i][0] == '\0') continue;
            double x = strtod(cells[i], NULL);
            if (cols[i].kind == COL_DEGREE) degree[cols[i].slot] = x;
            else value[cols[i].slot] = x;
        }
        lplace_engine_clear(e);
        for (size_t s = 0; s < n_slots; s++) {
            if (isnan(degree[s])) continue; /* not perceived */
            if (lplace_engine_set(e, (int)s, degree[s], value[s]) != LPLACE_OK) goto done;
        }
        LplaceDecision d;
        int rc = lplace_engine_step(e, &d);
        if (rc != LPLACE_OK) {
            fprintf(stderr, "controller: step failed with code %d\n", rc);
            goto done;
        }
        if (d.place >= 0) {
            printf("%lu,place,%s,", row, lplace_engine_place_name(e, (size_t)d.place));
            print_degree(d.necessity);
            printf(",,");
        } else {
            printf("%lu,disoriented,,,%s,", row, lplace_reason_name(d.reason));
        }
        print_degree(d.inconsistency);
        putchar('\n');
    }
    status = 0;
done:
    free(line);
    free(cells);
    free(cols);
    free(degree);
    free(value);
    return status;
}

int main(int argc, char **argv) {
    if (argc != 4) {
        fprintf(stderr, "usage: %s MAP RULES STREAM.csv\n", argv[0]);
        return 2;
    }
    char err[4096];
    LplaceEngine *e = lplace_engine_load(argv[1], argv[2], err, sizeof err);
    if (!e) {
        fprintf(stderr, "controller: %s\n", err);
        return 2;
    }
    FILE *in = fopen(argv[3], "r");
    if (!in) {
        perror(argv[3]);
        lplace_engine_free(e);
        return 2;
    }
    int status = check_contract(e) ? run(e, in) : 1;
    fclose(in);
    lplace_engine_free(e);
    return status;
}
