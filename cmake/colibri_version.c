/* The version string of the installed library (the modules are linked in whole). */
const char *cb_version(void);

const char *cb_version(void)
{
    return COLIBRI_VERSION;
}
