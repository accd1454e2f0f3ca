//! docs/config.md lists every config key: each of its sections against the keys the
//! config types accept, as serde's unknown-field error names them (so a field added to a
//! config struct without its row in the page, or a row left behind by a removed field,
//! fails here).

use std::collections::BTreeSet;

use logo_algo::config::TrainConfig;

/// Enough of a config to reach the table under test (its env given by the section's
/// TOML where that is an `[env]` table).
const BASE: &str = "iterations = 1\nsamples_per_iter = 1000\n";
const ENV: &str = "env = \"SparseHopper-v4\"\n";
const GUIDANCE: &str = "[guidance]\ndemos = \"d\"\ndelta0 = 0.1\nalpha = 0.9\nwarmup = 1\n";

/// Each section of the page (its heading after `## `), the TOML that puts an unknown key
/// into that table, and the tag key the section's kind is chosen by (not a struct field).
const SECTIONS: &[(&str, &str, Option<&str>)] = &[
    ("top level", "unknown_key = 1\n", None),
    (
        "`[env]`",
        "[env]\nid = \"Hopper-v4\"\nunknown_key = 1\n",
        None,
    ),
    (
        "`[env.sparse]`",
        "[env]\nid = \"Hopper-v4\"\n[env.sparse]\nkind = \"delayed\"\nunknown_key = 1\n",
        None,
    ),
    ("`[init]`", "[init]\nunknown_key = 1\n", None),
    ("`[reward]`", "[reward]\nunknown_key = 1\n", None),
    ("`[algorithm]`", "[algorithm]\nunknown_key = 1\n", None),
    (
        "`[demonstration_rows]`",
        "[demonstration_rows]\nunknown_key = 1\n",
        None,
    ),
    ("`[critic]`", "[critic]\nunknown_key = 1\n", None),
    (
        "`[critic.fit]`, `method = \"lbfgs\"`",
        "[critic.fit]\nmethod = \"lbfgs\"\nunknown_key = 1\n",
        Some("method"),
    ),
    (
        "`[critic.fit]`, `method = \"adam\"`",
        "[critic.fit]\nmethod = \"adam\"\nunknown_key = 1\n",
        Some("method"),
    ),
    (
        "`[improvement]`, `kind = \"trpo\"` or `\"clip-in-trpo\"`",
        "[improvement]\nkind = \"trpo\"\nunknown_key = 1\n",
        Some("kind"),
    ),
    (
        "`[improvement]`, `kind = \"npg\"`",
        "[improvement]\nkind = \"npg\"\nunknown_key = 1\n",
        Some("kind"),
    ),
    (
        "`[improvement]`, `kind = \"ppo-clip\"`",
        "[improvement]\nkind = \"ppo-clip\"\nunknown_key = 1\n",
        Some("kind"),
    ),
    (
        "`[improvement]`, `kind = \"ppo-penalty\"`",
        "[improvement]\nkind = \"ppo-penalty\"\nunknown_key = 1\n",
        Some("kind"),
    ),
    ("`[guidance]`", "unknown_key = 1\n", None),
];

/// The keys a table accepts: the backquoted names after "expected" in serde's error.
fn accepted(extra: &str, guidance: bool) -> BTreeSet<String> {
    let env = if extra.starts_with("[env]") { "" } else { ENV };
    let text = if guidance {
        format!("{BASE}{env}{GUIDANCE}{extra}")
    } else {
        format!("{BASE}{env}{extra}")
    };
    let error = toml::from_str::<TrainConfig>(&text)
        .expect_err("an unknown key must be refused")
        .to_string();
    let (_, listed) = error
        .split_once("expected")
        .unwrap_or_else(|| panic!("no field list in {error:?}"));
    let keys: BTreeSet<String> = listed
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    assert!(!keys.is_empty(), "no field list in {error:?}");
    keys
}

/// The key rows of the table under `## heading` (those opening with a backquoted key).
fn section_rows<'a>(page: &'a str, heading: &str) -> impl Iterator<Item = &'a str> {
    let start = page
        .lines()
        .position(|l| l.strip_prefix("## ") == Some(heading))
        .unwrap_or_else(|| panic!("docs/config.md has no section `## {heading}`"));
    page.lines()
        .skip(start + 1)
        .take_while(|l| !l.starts_with("## "))
        .filter(|l| l.starts_with("| `"))
}

/// The keys documented in the table under `## heading` (first column, backquoted).
fn documented(page: &str, heading: &str) -> BTreeSet<String> {
    section_rows(page, heading)
        .filter_map(|l| {
            l["| `".len()..]
                .split_once('`')
                .map(|(key, _)| key.to_string())
        })
        .collect()
}

#[test]
fn every_config_key_has_its_row_in_docs_config_md() {
    let page = std::fs::read_to_string(logo_testkit::workspace().join("docs/config.md"))
        .expect("docs/config.md");
    for &(heading, extra, tag) in SECTIONS {
        let mut want = accepted(extra, heading == "`[guidance]`");
        if let Some(tag) = tag {
            want.insert(tag.to_string());
        }
        assert_eq!(
            documented(&page, heading),
            want,
            "docs/config.md, section `{heading}`: its rows against the keys the config accepts"
        );
    }
}

#[test]
fn the_check_sees_a_key_missing_from_the_page() {
    let page = "## top level\n\n| key |\n| --- |\n| `env` | x |\n";
    assert_eq!(
        documented(page, "top level"),
        BTreeSet::from(["env".to_string()])
    );
    assert!(accepted("unknown_key = 1\n", false).len() > 20);
}

/// Each row of the section under `## heading`: (key, its default cell with backquotes
/// removed).
fn documented_defaults(page: &str, heading: &str) -> Vec<(String, String)> {
    section_rows(page, heading)
        .map(|l| {
            let cells: Vec<&str> = l.split('|').map(str::trim).collect();
            (
                cells[1].trim_matches('`').to_string(),
                cells[3].replace('`', ""),
            )
        })
        .collect()
}

/// A documented default and the value a config that leaves the key out holds: equal as
/// TOML values (an integer and a float of the same number are equal).
fn same_value(documented: &toml::Value, actual: &toml::Value) -> bool {
    use toml::Value::{Array, Float, Integer};
    match (documented, actual) {
        (Integer(a), Float(b)) | (Float(b), Integer(a)) => *a as f64 == *b,
        (Array(a), Array(b)) => {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| same_value(x, y))
        }
        (a, b) => a == b,
    }
}

/// The page's default column against the config types' own defaults: every row whose
/// default is a plain TOML value (a number, a string, a boolean, a list) must be what a
/// config without that key holds, so the page cannot drift from the one place each
/// default is set.
#[test]
fn every_default_on_the_page_is_the_configs_own() {
    let page = std::fs::read_to_string(logo_testkit::workspace().join("docs/config.md"))
        .expect("docs/config.md");
    let mut compared = 0;
    for &(heading, extra, tag) in SECTIONS {
        let guidance = heading == "`[guidance]`";
        let extra = extra.replace("unknown_key = 1\n", "");
        let env = if extra.starts_with("[env]") { "" } else { ENV };
        let text = format!("{BASE}{env}{}{extra}", if guidance { GUIDANCE } else { "" });
        let Ok(config) = toml::from_str::<TrainConfig>(&text) else {
            continue; // a table with required keys of its own ([algorithm], [env.sparse])
        };
        let stored = toml::Value::try_from(&config).unwrap();
        // The table the section's keys live in, as the run stores it.
        let path: Vec<&str> = extra
            .lines()
            .rev()
            .find_map(|l| l.strip_prefix('[')?.strip_suffix(']'))
            .map(|t| t.split('.').collect())
            .unwrap_or_default();
        let path = if guidance { vec!["guidance"] } else { path };
        let Some(table) = path.iter().try_fold(&stored, |v, key| v.get(key)) else {
            continue; // not stored when at its defaults ([init], [reward])
        };
        for (key, default) in documented_defaults(&page, heading) {
            let Ok(documented) = toml::from_str::<toml::Table>(&format!("v = {default}")) else {
                continue; // prose: "required", "none", "see [critic]", …
            };
            if Some(key.as_str()) == tag {
                continue; // the tag chooses the section's kind
            }
            let Some(actual) = table.get(&key) else {
                continue; // left out of stored configs at its default (`subsample`, `step`)
            };
            assert!(
                same_value(&documented["v"], actual),
                "docs/config.md, {heading} `{key}`: the page says {default}, the config holds {actual}"
            );
            compared += 1;
        }
    }
    assert!(compared >= 40, "only {compared} defaults compared");
}
