/* The corpus: every file in tests/data/bad must be rejected with a one-line message that starts
 * with the file's base name and ':'; every file in tests/data/good must parse. */
#define _POSIX_C_SOURCE 200809L
#include "io_test.h"

#include <dirent.h>

static int for_each_file(const char *dir, void (*fn)(const char *path, const char *name))
{
    DIR *d = opendir(dir);
    if (!d)
        fail_msg("cannot open %s", dir);
    int n = 0;
    struct dirent *de;
    while ((de = readdir(d)) != NULL) {
        if (de->d_name[0] == '.')
            continue;
        fn(iot_path(dir, de->d_name), de->d_name);
        ++n;
    }
    closedir(d);
    return n;
}

static void check_bad(const char *path, const char *name)
{
    sk_soup *s = NULL;
    sk_error e = {0};
    sk_status st = sk_soup_read(path, NULL, &s, &e);
    if (st == SK_OK)
        fail_msg("%s: accepted a bad file (%zu vertices, %zu faces)", name,
                 s ? s->num_vertices : 0, s ? s->num_faces : 0);
    assert_null(s);
    assert_true(st < 0);
    size_t n = strlen(name);
    if (strncmp(e.message, name, n) != 0 || e.message[n] != ':')
        fail_msg("%s: message does not start with '%s:': '%s'", name, name, e.message);
    if (strchr(e.message, '\n') || strchr(e.message, '\r'))
        fail_msg("%s: message is not one line", name);
    if (e.status != st)
        fail_msg("%s: err.status %d differs from the returned %d", name, e.status, st);
    print_message("  %-40s %s\n", name, e.message);
}

static void check_good(const char *path, const char *name)
{
    sk_soup *s = NULL;
    sk_error e = {0};
    if (sk_soup_read(path, NULL, &s, &e) != SK_OK)
        fail_msg("%s: %s", name, e.message);
    assert_true(s->num_vertices >= 3);
    assert_true(s->num_faces >= 1);
    sk_soup_destroy(&s);
}

static void test_bad_files(void **state)
{
    (void)state;
    assert_true(for_each_file(IOT_DATA "/bad", check_bad) >= 50);
}

static void test_good_files(void **state)
{
    (void)state;
    assert_true(for_each_file(IOT_DATA "/good", check_good) >= 15);
}

/* Reading a file that does not exist is an i/o error naming the path. */
static void test_missing_file(void **state)
{
    (void)state;
    sk_soup *s = NULL;
    sk_error e = {0};
    assert_int_equal(sk_soup_read(IOT_DATA "/no_such_file.off", NULL, &s, &e), SK_ERR_IO);
    assert_null(s);
    assert_non_null(strstr(e.message, "no_such_file.off"));
    assert_int_equal(sk_soup_read(IOT_DATA, NULL, &s, &e), SK_ERR_IO); /* a folder */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_files),
        cmocka_unit_test(test_good_files),
        cmocka_unit_test(test_missing_file),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
