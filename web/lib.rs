//! raylab's own chapters for the browser page: `web/page/` loads the
//! WebAssembly this builds (scripts/build-web.sh) and calls the functions
//! raylab's `web_exports!` defines. A student workspace's page is built
//! the same way from a crate that names the student's chapters instead
//! (`raylab web` in the workspace).

raylab::web_exports!(raylab::Reference);
