//! `tensorglyph report` on the BEP016 derivatives of tests/data/bids (DIPY's and MRtrix's fits
//! of DIPY's DWI sets): every good participant's figures and page, the broken one named, exit
//! status 1; pages that need nothing but themselves.

use std::path::Path;

use base64::Engine as _;

use crate::cli::{stderr, tg};

fn bids() -> String {
    crate::data::path("bids/derivatives")
        .to_string_lossy()
        .into_owned()
}

/// The PNG images a page embeds, decoded from their data URLs.
fn embedded(html: &str) -> Vec<Vec<u8>> {
    html.split("src=\"data:image/png;base64,")
        .skip(1)
        .map(|s| {
            let b64 = &s[..s.find('"').unwrap()];
            base64::engine::general_purpose::STANDARD
                .decode(b64)
                .unwrap()
        })
        .collect()
}

#[test]
fn every_good_participant_is_written_and_the_broken_one_is_named() {
    let out = tempfile::tempdir().unwrap();
    let o = tg(&[
        "report",
        &bids(),
        out.path().to_str().unwrap(),
        "participant",
    ]);
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(errors[0].starts_with("error: sub-04: "), "{err}");
    assert!(
        errors[0].contains("gzip data is corrupt or truncated"),
        "{err}"
    );
    // Nothing of the broken one.
    assert!(!out.path().join("sub-04.html").exists());
    assert!(!out.path().join("sub-04").exists());
    let description: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.path().join("dataset_description.json")).unwrap(),
    )
    .unwrap();
    assert_eq!(description["DatasetType"], "derivative");
    for (label, maps, axes) in [
        ("01", 1, "ijk"),
        ("02", 1, "xyz"),
        ("03", 2, "ijk"),
        ("05", 1, "xyz"),
    ] {
        let html = std::fs::read_to_string(out.path().join(format!("sub-{label}.html"))).unwrap();
        // Self-contained: nothing fetched from anywhere.
        assert!(
            !html.contains("http:") && !html.contains("https:"),
            "sub-{label}"
        );
        assert_eq!(html.matches("src=").count(), 3 * maps, "sub-{label}");
        assert!(
            html.contains(&format!("ReferenceAxes {axes} from the BEP016 sidecar")),
            "sub-{label}"
        );
        assert!(
            html.contains("fsl (from the BEP016 sidecar)"),
            "sub-{label}"
        );
        // The figures on disk are the images on the page, 480 pixels a side.
        let images = embedded(&html);
        let mut files: Vec<_> = std::fs::read_dir(out.path().join(format!("sub-{label}/figures")))
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        files.sort();
        assert_eq!(files.len(), 3 * maps);
        for f in &files {
            let png = std::fs::read(f).unwrap();
            assert!(images.contains(&png), "{} not on the page", f.display());
            let img = image::load_from_memory(&png).unwrap();
            assert_eq!((img.width(), img.height()), (480, 480));
        }
    }
    let sub3 = std::fs::read_to_string(out.path().join("sub-03.html")).unwrap();
    assert!(sub3.contains("<th>session</th><td>1</td>") && sub3.contains("<td>2</td>"));
}

#[test]
fn chosen_participants_only_and_usage_errors() {
    let out = tempfile::tempdir().unwrap();
    let o = tg(&[
        "report",
        &bids(),
        out.path().to_str().unwrap(),
        "participant",
        "--participant-label",
        "sub-01",
        "02",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    let mut names: Vec<String> = std::fs::read_dir(out.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "dataset_description.json",
            "sub-01",
            "sub-01.html",
            "sub-02",
            "sub-02.html"
        ]
    );
    for (args, want) in [
        (vec!["group"], "group"),
        (
            vec!["participant", "--participant-label", "99"],
            "no participant 99",
        ),
    ] {
        let b = bids();
        let mut all = vec!["report", &b, out.path().to_str().unwrap()];
        all.extend(args.iter().copied());
        let o = tg(&all);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(want), "{err}");
    }
    assert!(!Path::new(&bids()).join("sub-01.html").exists());
}
