/* tests/spu/options_test.c — parsing and validating typed SPU options
 * (core/spu/options.c, compiled in): every type, ranges, bad values, lists,
 * defaults, and the did-you-mean suggestion. Owns nothing. Never: checks a
 * message loosely when the exact text is the contract. */
#include <math.h>

#include "options.h"
#include "spu_test.h"

#define NO_RANGE .min = 1, .max = 0

/* Parses `value` for the single option `spec` of an SPU called "render";
 * value NULL means the option is not given (its default applies). */
static tsr_options *parse1(const tsr_option_spec *spec, const char *value, tsr_error *err)
{
    tsr_option_group group = {"render", spec, 1};
    const char *keys[1] = {spec->name};
    const char *values[1] = {value};
    tsr_error_clear(err);
    return tsr_options_parse("render", &group, 1, keys, values, value ? 1 : 0, err);
}

/* The error message of parsing `value`, "" when it parsed. */
static const char *parse_error(const tsr_option_spec *spec, const char *value)
{
    static tsr_error err;
    tsr_options *o = parse1(spec, value, &err);
    if (o) {
        tsr_options_free(o);
        return "";
    }
    CHECK(err.code == TSR_EINVAL);
    return err.message;
}

static void test_bool(void)
{
    const tsr_option_spec spec = {.name = "verbose", .type = TSR_OPT_BOOL, NO_RANGE};
    static const char *const truthy[] = {"true", "yes", "on", "1", "TRUE", "Yes"};
    static const char *const falsy[] = {"false", "no", "off", "0", "OFF"};
    tsr_error err;
    for (size_t i = 0; i < sizeof truthy / sizeof *truthy; i++) {
        tsr_options *o = parse1(&spec, truthy[i], &err);
        REQUIRE(o);
        CHECK(tsr_options_bool(o, "verbose") == true);
        tsr_options_free(o);
    }
    for (size_t i = 0; i < sizeof falsy / sizeof *falsy; i++) {
        tsr_options *o = parse1(&spec, falsy[i], &err);
        REQUIRE(o);
        CHECK(tsr_options_bool(o, "verbose") == false);
        tsr_options_free(o);
    }
    CHECK_STR(parse_error(&spec, "maybe"),
              "render: option 'verbose': 'maybe' is not a boolean (true/false, yes/no, on/off, "
              "1/0)");
    CHECK_STR(parse_error(&spec, ""),
              "render: option 'verbose': '' is not a boolean (true/false, yes/no, on/off, 1/0)");
}

static void test_int(void)
{
    const tsr_option_spec spec = {
        .name = "width", .type = TSR_OPT_INT, .default_value = "1024", .min = 1, .max = 16384};
    tsr_error err;
    tsr_options *o = parse1(&spec, "640", &err);
    REQUIRE(o);
    CHECK(tsr_options_int(o, "width") == 640);
    tsr_options_free(o);
    o = parse1(&spec, "+16384", &err);
    REQUIRE(o);
    CHECK(tsr_options_int(o, "width") == 16384);
    tsr_options_free(o);
    /* Base 10 always: a leading zero is not octal. */
    o = parse1(&spec, "010", &err);
    REQUIRE(o);
    CHECK(tsr_options_int(o, "width") == 10);
    tsr_options_free(o);
    CHECK_STR(parse_error(&spec, "abc"), "render: option 'width': 'abc' is not an integer");
    CHECK_STR(parse_error(&spec, "0"), "render: option 'width': '0' is out of range [1, 16384]");
    CHECK_STR(parse_error(&spec, "16385"), "render: option 'width': '16385' is out of range [1, 16384]");
}

static void test_int_rejects_junk_and_overflow(void)
{
    const tsr_option_spec spec = {.name = "count", .type = TSR_OPT_INT, NO_RANGE};
    CHECK_STR(parse_error(&spec, "12px"), "render: option 'count': '12px' is not an integer");
    CHECK_STR(parse_error(&spec, " 12"), "render: option 'count': ' 12' is not an integer");
    CHECK_STR(parse_error(&spec, "12 "), "render: option 'count': '12 ' is not an integer");
    CHECK_STR(parse_error(&spec, "1.5"), "render: option 'count': '1.5' is not an integer");
    CHECK_STR(parse_error(&spec, ""), "render: option 'count': '' is not an integer");
    CHECK_STR(parse_error(&spec, "-"), "render: option 'count': '-' is not an integer");
    CHECK_STR(parse_error(&spec, "99999999999999999999"),
              "render: option 'count': '99999999999999999999' does not fit in a 64-bit integer");
    tsr_error err;
    tsr_options *o = parse1(&spec, "-9223372036854775808", &err);
    REQUIRE(o);
    CHECK(tsr_options_int(o, "count") == INT64_MIN);
    tsr_options_free(o);
}

static void test_float(void)
{
    const tsr_option_spec spec = {.name = "gamma", .type = TSR_OPT_FLOAT, .default_value = "2.2", .min = 0.5, .max = 4};
    tsr_error err;
    tsr_options *o = parse1(&spec, "1.8", &err);
    REQUIRE(o);
    CHECK(tsr_options_float(o, "gamma") == 1.8);
    tsr_options_free(o);
    o = parse1(&spec, ".75", &err);
    REQUIRE(o);
    CHECK(tsr_options_float(o, "gamma") == 0.75);
    tsr_options_free(o);
    o = parse1(&spec, "3e0", &err);
    REQUIRE(o);
    CHECK(tsr_options_float(o, "gamma") == 3.0);
    tsr_options_free(o);
    CHECK_STR(parse_error(&spec, "bright"), "render: option 'gamma': 'bright' is not a number");
    CHECK_STR(parse_error(&spec, "1.5x"), "render: option 'gamma': '1.5x' is not a number");
    CHECK_STR(parse_error(&spec, "0.25"), "render: option 'gamma': '0.25' is out of range [0.5, 4]");
}

static void test_float_rejects_nan_and_inf(void)
{
    const tsr_option_spec spec = {.name = "scale", .type = TSR_OPT_FLOAT, NO_RANGE};
    CHECK_STR(parse_error(&spec, "nan"), "render: option 'scale': 'nan' is not a finite number");
    CHECK_STR(parse_error(&spec, "-inf"), "render: option 'scale': '-inf' is not a finite number");
    CHECK_STR(parse_error(&spec, "1e999"), "render: option 'scale': '1e999' is not a finite number");
}

static void test_string(void)
{
    const tsr_option_spec spec = {.name = "output", .type = TSR_OPT_STRING, .default_value = "out-%04d.png", NO_RANGE};
    tsr_error err;
    tsr_options *o = parse1(&spec, "frames/f 1.png", &err);
    REQUIRE(o);
    CHECK_STR(tsr_options_string(o, "output"), "frames/f 1.png");
    tsr_options_free(o);
    o = parse1(&spec, "", &err);
    REQUIRE(o);
    CHECK_STR(tsr_options_string(o, "output"), "");
    tsr_options_free(o);
    o = parse1(&spec, NULL, &err);
    REQUIRE(o);
    CHECK_STR(tsr_options_string(o, "output"), "out-%04d.png");
    tsr_options_free(o);
}

static void test_enum(void)
{
    const tsr_option_spec spec = {.name = "bucket",
                                  .type = TSR_OPT_ENUM,
                                  .default_value = "grid",
                                  NO_RANGE,
                                  .choices = "grid|broadcast|balanced"};
    tsr_error err;
    tsr_options *o = parse1(&spec, "balanced", &err);
    REQUIRE(o);
    CHECK_STR(tsr_options_string(o, "bucket"), "balanced");
    tsr_options_free(o);
    CHECK_STR(parse_error(&spec, "Grid"),
              "render: option 'bucket': 'Grid' is not one of grid|broadcast|balanced (did you "
              "mean 'grid'?)");
    CHECK_STR(parse_error(&spec, "tiles"), "render: option 'bucket': 'tiles' is not one of grid|broadcast|balanced");
    CHECK_STR(parse_error(&spec, "gri"),
              "render: option 'bucket': 'gri' is not one of grid|broadcast|balanced (did you "
              "mean 'grid'?)");
}

static void test_int_list(void)
{
    const tsr_option_spec spec = {.name = "tile", .type = TSR_OPT_INT_LIST, .min = 0, .max = 4096};
    tsr_error err;
    tsr_options *o = parse1(&spec, "0,0, 512 ,768", &err);
    REQUIRE(o);
    REQUIRE(tsr_options_count(o, "tile") == 4);
    CHECK(tsr_options_int_at(o, "tile", 0) == 0);
    CHECK(tsr_options_int_at(o, "tile", 2) == 512);
    CHECK(tsr_options_int_at(o, "tile", 3) == 768);
    tsr_options_free(o);
    o = parse1(&spec, "", &err);
    REQUIRE(o);
    CHECK(tsr_options_count(o, "tile") == 0);
    tsr_options_free(o);
    CHECK_STR(parse_error(&spec, "1,x,3"), "render: option 'tile': element 2 of '1,x,3': 'x' is not an integer");
    CHECK_STR(parse_error(&spec, "1,5000"),
              "render: option 'tile': element 2 of '1,5000': '5000' is out of range [0, 4096]");
    CHECK_STR(parse_error(&spec, "1,,3"), "render: option 'tile': element 2 of '1,,3': '' is not an integer");
}

static void test_float_list(void)
{
    const tsr_option_spec spec = {.name = "clear_color", .type = TSR_OPT_FLOAT_LIST, .min = 0, .max = 1};
    tsr_error err;
    tsr_options *o = parse1(&spec, "0.25,0.5,1", &err);
    REQUIRE(o);
    REQUIRE(tsr_options_count(o, "clear_color") == 3);
    CHECK(tsr_options_float_at(o, "clear_color", 0) == 0.25);
    CHECK(tsr_options_float_at(o, "clear_color", 2) == 1.0);
    tsr_options_free(o);
    CHECK_STR(parse_error(&spec, "0.5,1.5"),
              "render: option 'clear_color': element 2 of '0.5,1.5': '1.5' is out of range [0, "
              "1]");
    CHECK_STR(parse_error(&spec, "0.5,nan"),
              "render: option 'clear_color': element 2 of '0.5,nan': 'nan' is not a finite "
              "number");
}

static void test_string_list(void)
{
    const tsr_option_spec spec = {.name = "peers", .type = TSR_OPT_STRING_LIST, .default_value = "a,b", NO_RANGE};
    tsr_error err;
    tsr_options *o = parse1(&spec, "wall0, wall1,wall2", &err);
    REQUIRE(o);
    REQUIRE(tsr_options_count(o, "peers") == 3);
    CHECK_STR(tsr_options_string_at(o, "peers", 0), "wall0");
    CHECK_STR(tsr_options_string_at(o, "peers", 1), "wall1");
    CHECK_STR(tsr_options_string_at(o, "peers", 2), "wall2");
    CHECK(tsr_options_string_at(o, "peers", 3) == NULL);
    tsr_options_free(o);
    o = parse1(&spec, NULL, &err);
    REQUIRE(o);
    CHECK(tsr_options_count(o, "peers") == 2);
    CHECK_STR(tsr_options_string_at(o, "peers", 1), "b");
    tsr_options_free(o);
}

static const tsr_option_spec render_specs[] = {
    {.name = "width", .type = TSR_OPT_INT, .default_value = "1024", .min = 1, .max = 16384, .help = "window width"},
    {.name = "height", .type = TSR_OPT_INT, .default_value = "768", .min = 1, .max = 16384},
    {.name = "output", .type = TSR_OPT_STRING, .default_value = "", NO_RANGE},
    {.name = "depth", .type = TSR_OPT_BOOL, NO_RANGE},
    {.name = "mode", .type = TSR_OPT_ENUM, NO_RANGE, .choices = "color|depth"},
    {.name = "tiles", .type = TSR_OPT_INT_LIST, NO_RANGE},
};
#define RENDER_SPEC_COUNT (sizeof render_specs / sizeof render_specs[0])

static const char *parse_render(const char *key, const char *value)
{
    static tsr_error err;
    tsr_option_group group = {"render", render_specs, RENDER_SPEC_COUNT};
    tsr_error_clear(&err);
    tsr_options *o = tsr_options_parse("render", &group, 1, &key, &value, 1, &err);
    tsr_options_free(o);
    return o ? "" : err.message;
}

static void test_defaults(void)
{
    tsr_error err;
    tsr_option_group group = {"render", render_specs, RENDER_SPEC_COUNT};
    CHECK(tsr_option_specs_check("render", render_specs, RENDER_SPEC_COUNT, &err) == TSR_OK);
    tsr_options *o = tsr_options_parse("render", &group, 1, NULL, NULL, 0, &err);
    REQUIRE(o);
    CHECK(tsr_options_int(o, "width") == 1024);
    CHECK(tsr_options_int(o, "height") == 768);
    CHECK_STR(tsr_options_string(o, "output"), "");
    /* No default: the type's zero value, or an enum's first choice. */
    CHECK(tsr_options_bool(o, "depth") == false);
    CHECK_STR(tsr_options_string(o, "mode"), "color");
    CHECK(tsr_options_count(o, "tiles") == 0);
    tsr_options_free(o);
}

static void test_did_you_mean(void)
{
    CHECK_STR(parse_render("widht", "5"), "render: unknown option 'widht' (did you mean 'width'?)");
    CHECK_STR(parse_render("heigth", "5"), "render: unknown option 'heigth' (did you mean 'height'?)");
    CHECK_STR(parse_render("outpt", "x"), "render: unknown option 'outpt' (did you mean 'output'?)");
    CHECK_STR(parse_render("color", "red"),
              "render: unknown option 'color' (options: width, height, output, depth, mode, "
              "tiles)");
    CHECK(tsr_edit_distance("widht", "width") == 1);
    CHECK(tsr_edit_distance("", "abc") == 3);
    CHECK(tsr_edit_distance("kitten", "sitting") == 3);
}

static void test_given_twice(void)
{
    tsr_error err;
    tsr_option_group group = {"render", render_specs, RENDER_SPEC_COUNT};
    const char *keys[] = {"width", "width"}, *values[] = {"1", "2"};
    tsr_options *o = tsr_options_parse("render", &group, 1, keys, values, 2, &err);
    CHECK(o == NULL);
    CHECK_STR(err.message, "render: option 'width' is given twice");
    tsr_options_free(o);
}

static void test_bad_default_is_class_error(void)
{
    tsr_error err;
    const tsr_option_spec bad_int[] = {
        {.name = "width", .type = TSR_OPT_INT, .default_value = "wide", .min = 1, .max = 10}};
    CHECK(tsr_option_specs_check("badspu", bad_int, 1, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 'width': bad default: 'wide' is not an integer");
    const tsr_option_spec out_of_range[] = {{.name = "level", .type = TSR_OPT_INT, .min = 1, .max = 9}};
    CHECK(tsr_option_specs_check("badspu", out_of_range, 1, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 'level': bad default: '0' is out of range [1, 9]");
    const tsr_option_spec bad_enum[] = {
        {.name = "mode", .type = TSR_OPT_ENUM, .default_value = "c", NO_RANGE, .choices = "a|b"}};
    CHECK(tsr_option_specs_check("badspu", bad_enum, 1, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 'mode': bad default: 'c' is not one of a|b");
    const tsr_option_spec no_choices[] = {{.name = "mode", .type = TSR_OPT_ENUM, NO_RANGE}};
    CHECK(tsr_option_specs_check("badspu", no_choices, 1, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 'mode': enum choices '(null)' must be names separated by '|'");
    const tsr_option_spec bad_name[] = {{.name = "Width", .type = TSR_OPT_INT, NO_RANGE}};
    CHECK(tsr_option_specs_check("badspu", bad_name, 1, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 1: 'Width' is not a lower_snake_case name");
    const tsr_option_spec twice[] = {{.name = "a", .type = TSR_OPT_INT, NO_RANGE},
                                     {.name = "a", .type = TSR_OPT_BOOL, NO_RANGE}};
    CHECK(tsr_option_specs_check("badspu", twice, 2, &err) == TSR_EINVAL);
    CHECK_STR(err.message, "badspu: option 'a' is declared twice");
}

static void test_subclass_overrides_super(void)
{
    /* readback inherits render: it accepts render's options, and its own
     * declaration of `output` (another default) wins over render's. */
    const tsr_option_spec readback_specs[] = {
        {.name = "output", .type = TSR_OPT_STRING, .default_value = "net", NO_RANGE},
        {.name = "send_depth", .type = TSR_OPT_BOOL, .default_value = "yes", NO_RANGE},
    };
    tsr_option_group groups[] = {{"readback", readback_specs, 2}, {"render", render_specs, RENDER_SPEC_COUNT}};
    tsr_error err;
    const char *keys[] = {"width"}, *values[] = {"300"};
    tsr_options *o = tsr_options_parse("readback", groups, 2, keys, values, 1, &err);
    REQUIRE(o);
    CHECK(tsr_options_int(o, "width") == 300);
    CHECK(tsr_options_int(o, "height") == 768);
    CHECK_STR(tsr_options_string(o, "output"), "net");
    CHECK(tsr_options_bool(o, "send_depth") == true);
    tsr_options_free(o);
    const char *bad_keys[] = {"send_dpth"}, *bad_values[] = {"no"};
    CHECK(tsr_options_parse("readback", groups, 2, bad_keys, bad_values, 1, &err) == NULL);
    CHECK_STR(err.message, "readback: unknown option 'send_dpth' (did you mean 'send_depth'?)");
}

static void test_accessor_wrong_type_returns_zero(void)
{
    tsr_error err;
    tsr_option_group group = {"render", render_specs, RENDER_SPEC_COUNT};
    tsr_options *o = tsr_options_parse("render", &group, 1, NULL, NULL, 0, &err);
    REQUIRE(o);
    /* Programming errors: logged, and a zero value instead of a crash. */
    CHECK(tsr_options_bool(o, "width") == false);
    CHECK(tsr_options_int(o, "nonexistent") == 0);
    CHECK(tsr_options_string(o, "width") == NULL);
    CHECK(tsr_options_count(o, "width") == 0);
    CHECK(tsr_options_int_at(o, "tiles", 0) == 0);
    CHECK(isnan(tsr_options_float(o, "width")) == 0);
    tsr_options_free(o);
}

static const spu_test_case tests[] = {
    {"spu_options_parse_bool", test_bool},
    {"spu_options_parse_int_range", test_int},
    {"spu_options_parse_int_rejects_junk_and_overflow", test_int_rejects_junk_and_overflow},
    {"spu_options_parse_float_range", test_float},
    {"spu_options_parse_float_rejects_nan_and_inf", test_float_rejects_nan_and_inf},
    {"spu_options_parse_string", test_string},
    {"spu_options_parse_enum", test_enum},
    {"spu_options_parse_int_list", test_int_list},
    {"spu_options_parse_float_list", test_float_list},
    {"spu_options_parse_string_list", test_string_list},
    {"spu_options_parse_defaults", test_defaults},
    {"spu_options_parse_did_you_mean", test_did_you_mean},
    {"spu_options_parse_given_twice", test_given_twice},
    {"spu_options_parse_bad_default_is_class_error", test_bad_default_is_class_error},
    {"spu_options_parse_subclass_overrides_super", test_subclass_overrides_super},
    {"spu_options_parse_accessor_wrong_type_returns_zero", test_accessor_wrong_type_returns_zero},
};

SPU_TEST_MAIN(tests)
