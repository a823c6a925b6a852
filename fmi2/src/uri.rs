//! `fmuResourceLocation` handling: file URIs to paths.

use std::path::PathBuf;

/// Converts a `file:` URI (as passed to `fmi2Instantiate`) to a local path.
///
/// Accepts `file:///abs/path`, `file://localhost/abs/path`, `file:/abs/path` (the FMI 2.0
/// standard's own example form) and, leniently, a plain absolute path. Percent-escapes are
/// decoded (`%20` → space). Other hosts and schemes are refused.
///
/// On Windows the URI's path names a drive, `file:///C:/Users/x/resources`: the slash before the
/// drive letter is dropped (`C:/Users/x/resources`), and a plain `C:\...` path is accepted too.
pub fn file_uri_to_path(uri: &str) -> Result<PathBuf, String> {
    file_uri_to_path_for(uri, cfg!(windows))
}

/// [`file_uri_to_path`] for a Windows (`windows`) or a Unix file system: testable on either.
fn file_uri_to_path_for(uri: &str, windows: bool) -> Result<PathBuf, String> {
    let rest = if let Some(r) = strip_prefix_ci(uri, "file:") {
        r
    } else if uri.starts_with('/') || (windows && drive_prefixed(uri)) {
        return Ok(PathBuf::from(uri));
    } else {
        return Err(format!(
            "resource location '{uri}' is not a file: URI (only local files are supported)"
        ));
    };
    let path = if let Some(after) = rest.strip_prefix("//") {
        // authority follows up to the next '/'
        let (host, path) = match after.find('/') {
            Some(i) => (&after[..i], &after[i..]),
            None => (after, "/"),
        };
        if !(host.is_empty() || host.eq_ignore_ascii_case("localhost")) {
            return Err(format!(
                "resource location '{uri}' names the host '{host}': only local files are supported"
            ));
        }
        path
    } else {
        rest
    };
    if !path.starts_with('/') {
        return Err(format!(
            "resource location '{uri}' is not an absolute file URI"
        ));
    }
    let decoded = percent_decode(path)
        .ok_or_else(|| format!("resource location '{uri}' has an invalid percent-escape"))?;
    // `/C:/x` -> `C:/x` on Windows, where a path starting with `/` is relative to the current drive.
    match decoded.strip_prefix('/') {
        Some(p) if windows && drive_prefixed(p) => Ok(PathBuf::from(p)),
        _ => Ok(PathBuf::from(decoded)),
    }
}

/// `C:` alone or followed by a separator.
fn drive_prefixed(s: &str) -> bool {
    let b = s.as_bytes();
    b.len() >= 2
        && b[0].is_ascii_alphabetic()
        && b[1] == b':'
        && (b.len() == 2 || b[2] == b'/' || b[2] == b'\\')
}

fn strip_prefix_ci<'a>(s: &'a str, prefix: &str) -> Option<&'a str> {
    if s.len() >= prefix.len() && s[..prefix.len()].eq_ignore_ascii_case(prefix) {
        Some(&s[prefix.len()..])
    } else {
        None
    }
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hi = (*b.get(i + 1)? as char).to_digit(16)?;
            let lo = (*b.get(i + 2)? as char).to_digit(16)?;
            out.push((hi * 16 + lo) as u8);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn forms() {
        let p = |s| file_uri_to_path(s).unwrap().to_string_lossy().into_owned();
        assert_eq!(p("file:///tmp/a%20b/resources"), "/tmp/a b/resources");
        assert_eq!(p("file:/tmp/x/resources/"), "/tmp/x/resources/");
        assert_eq!(p("file://localhost/tmp/x"), "/tmp/x");
        assert_eq!(p("FILE:///tmp/%C3%A9"), "/tmp/é");
        assert_eq!(p("/plain/path"), "/plain/path");
        assert!(file_uri_to_path("http://example.org/x").is_err());
        assert!(file_uri_to_path("file://server/share").is_err());
        assert!(file_uri_to_path("file:///bad%2").is_err());
        assert!(file_uri_to_path("file:relative").is_err());
    }

    #[test]
    fn windows_drives() {
        let w = |s| {
            file_uri_to_path_for(s, true)
                .unwrap()
                .to_string_lossy()
                .into_owned()
        };
        assert_eq!(
            w("file:///C:/Users/a%20b/resources"),
            "C:/Users/a b/resources"
        );
        assert_eq!(w("file:/c:/x"), "c:/x");
        assert_eq!(w("file://localhost/D:/x/"), "D:/x/");
        assert_eq!(w("C:\\x\\resources"), "C:\\x\\resources");
        assert_eq!(w("file:///tmp/x"), "/tmp/x");
        // On Unix the same URI is a path whose first component is `C:`.
        let u = file_uri_to_path_for("file:///C:/x", false).unwrap();
        assert_eq!(u.to_string_lossy(), "/C:/x");
        assert!(file_uri_to_path_for("C:\\x", false).is_err());
    }
}
