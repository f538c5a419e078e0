//! The page's elements the viewer writes to (web-sys).

use base64::Engine as _;

fn document() -> Option<web_sys::Document> {
    web_sys::window()?.document()
}

/// Set the text of the element with id `id` (absent elements are skipped: the page decides
/// what it shows).
pub fn set_text(id: &str, text: &str) {
    if let Some(e) = document().and_then(|d| d.get_element_by_id(id)) {
        e.set_text_content(Some(text));
    }
}

/// Mark the page busy while something loads or renders (`<body aria-busy>`).
pub fn set_busy(busy: bool) {
    if let Some(body) = document().and_then(|d| d.body()) {
        let _ = body.set_attribute("aria-busy", if busy { "true" } else { "false" });
    }
}

/// Show a PNG as `<img id="figure">` (a data URL: nothing leaves the page), with
/// `<a id="figure-link">` downloading it as `name`, and reveal `#figure-box`.
pub fn show_figure(png: &[u8], name: &str) -> Result<(), String> {
    let doc = document().ok_or("no document")?;
    let url = format!(
        "data:image/png;base64,{}",
        base64::engine::general_purpose::STANDARD.encode(png)
    );
    let element = |id: &str| {
        doc.get_element_by_id(id)
            .ok_or_else(|| format!("the page has no #{id}"))
    };
    element("figure")?
        .set_attribute("src", &url)
        .map_err(|_| "cannot set the figure")?;
    let link = element("figure-link")?;
    let _ = link.set_attribute("href", &url);
    let _ = link.set_attribute("download", name);
    let _ = element("figure-box")?.remove_attribute("hidden");
    Ok(())
}
