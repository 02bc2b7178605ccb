/* core/util/names.c — "did you mean" for error messages (tessera/dev/util.h):
 * edit distance (optimal string alignment: insert, delete, substitute, swap
 * adjacent) and the closest candidate within two edits. Owns nothing;
 * never allocates (words over TSR_SUGGEST_MAX_LEN are not compared). */
#include "tessera/dev/util.h"

#include <string.h>


size_t tsr_edit_distance(const char *a, const char *b)
{
    size_t la = strlen(a), lb = strlen(b);
    if (la > TSR_SUGGEST_MAX_LEN || lb > TSR_SUGGEST_MAX_LEN)
        return (size_t)-1;
    /* Three rolling rows of the optimal-string-alignment matrix. */
    size_t rows[3][TSR_SUGGEST_MAX_LEN + 1];
    size_t *prev2 = rows[0], *prev = rows[1], *cur = rows[2];
    for (size_t j = 0; j <= lb; j++)
        prev[j] = j;
    for (size_t i = 1; i <= la; i++) {
        cur[0] = i;
        for (size_t j = 1; j <= lb; j++) {
            size_t cost = a[i - 1] != b[j - 1];
            size_t best = prev[j] + 1;
            if (cur[j - 1] + 1 < best)
                best = cur[j - 1] + 1;
            if (prev[j - 1] + cost < best)
                best = prev[j - 1] + cost;
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] && prev2[j - 2] + 1 < best)
                best = prev2[j - 2] + 1;
            cur[j] = best;
        }
        size_t *t = prev2;
        prev2 = prev;
        prev = cur;
        cur = t;
    }
    return prev[lb];
}

const char *tsr_closest_name(const char *word, const char *const *candidates, size_t count)
{
    const char *best = NULL;
    size_t best_distance = (size_t)-1;
    size_t word_len = strlen(word);
    for (size_t i = 0; i < count; i++) {
        size_t d = tsr_edit_distance(word, candidates[i]);
        /* A typo is at most two edits, and never the whole word ('x' is not
         * a misspelling of 'y'). */
        if (d <= 2 && d < word_len && d < strlen(candidates[i]) && d < best_distance) {
            best = candidates[i];
            best_distance = d;
        }
    }
    return best;
}
