/*
 * cli_json.c - loading and editing request JSON for the refract CLI (see cli_json.h).
 *
 * Request files are parsed here only when flags must be merged into them; a request
 * sent unchanged goes to refractd untouched, which validates it and names the path of
 * any mistake. Parsing follows STYLE: cJSON_ParseWithLengthOpts with a length, never
 * cJSON_GetErrorPtr, and the position of a syntax error comes from return_parse_end.
 */
#include "cli_json.h"

#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* 1-based line and column of offset in text, for "not JSON at line L, column C". */
static void line_column(const char *text, size_t offset, size_t *line, size_t *column)
{
    *line = 1;
    *column = 1;
    for (size_t i = 0; i < offset; i++) {
        if (text[i] == '\n') {
            (*line)++;
            *column = 1;
        } else {
            (*column)++;
        }
    }
}

int cli_json_load_object(const char *path, const char *option, cJSON **out)
{
    const char *end = NULL;
    char *text = NULL;
    size_t len = 0;
    int code = cli_read_file(path, &text, &len);

    *out = NULL;
    if (code != REFRACT_E_OK)
        return code;
    *out = cJSON_ParseWithLengthOpts(text, len, &end, 0);
    if (*out == NULL) {
        size_t line;
        size_t column;
        size_t at = end != NULL && end >= text && end <= text + len ? (size_t)(end - text) : 0;

        line_column(text, at, &line, &column);
        code = cli_fail(REFRACT_E_INVALID_JSON,
                        "%s '%s': not valid JSON near line %zu, "
                        "column %zu",
                        option, path, line, column);
    } else if (!cJSON_IsObject(*out)) {
        code = cli_fail(REFRACT_E_INVALID_FIELD, "%s '%s': expected a JSON object {...}", option,
                        path);
        cJSON_Delete(*out);
        *out = NULL;
    }
    free(text);
    return code;
}

bool cli_json_set(cJSON *obj, const char *key, cJSON *item)
{
    if (item == NULL)
        return false;
    if (cJSON_GetObjectItemCaseSensitive(obj, key) != NULL) {
        if (cJSON_ReplaceItemInObjectCaseSensitive(obj, key, item))
            return true;
        cJSON_Delete(item);
        return false;
    }
    if (!cJSON_AddItemToObject(obj, key, item)) {
        cJSON_Delete(item);
        return false;
    }
    return true;
}

cJSON *cli_json_object_member(cJSON *obj, const char *key)
{
    cJSON *member = cJSON_GetObjectItemCaseSensitive(obj, key);

    if (member != NULL)
        return cJSON_IsObject(member) ? member : NULL;
    member = cJSON_CreateObject();
    return cli_json_set(obj, key, member) ? member : NULL;
}
