//! The settings table is the library's: every stated default, given
//! explicitly, makes the same request as leaving every option out, and
//! every range refuses what the library refuses, naming the option.

use serde_json::{Map, Value};
use sssbake_io::BakeOptions;
use sssbake_io::settings::{Kind, SETTINGS};
use std::path::Path;

fn marble() -> &'static Path {
    Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/marble/marble.gltf"
    ))
}

#[test]
fn the_stated_defaults_are_the_librarys() {
    let mut stated = Map::new();
    for setting in SETTINGS.iter() {
        if let Some(value) = &setting.default {
            setting.check(value).expect("a default is in its own range");
            stated.insert(setting.name.to_string(), value.clone());
        }
    }
    assert!(stated.len() > 15, "{} defaults stated", stated.len());
    let given: BakeOptions = serde_json::from_value(Value::Object(stated)).unwrap();
    let (_, explicit) = given.load(marble()).unwrap();
    let (_, left_out) = BakeOptions::default().load(marble()).unwrap();
    assert_eq!(format!("{explicit:?}"), format!("{left_out:?}"));
    let folder = |o: &BakeOptions| format!("{:?}", o.folder(Path::new("out"), false));
    assert_eq!(folder(&given), folder(&BakeOptions::default()));
}

#[test]
fn every_range_refuses_past_its_ends_naming_the_option() {
    for setting in SETTINGS.iter() {
        let past: Vec<Value> = match &setting.kind {
            Kind::Count { min, max } => {
                let mut v = vec![];
                if *min > 0 {
                    v.push(Value::from(min - 1));
                }
                if *max < u64::from(u32::MAX) {
                    v.push(Value::from(max + 1));
                }
                v
            }
            Kind::Number {
                min,
                min_exclusive,
                max,
            } => {
                let mut v = vec![];
                if let Some(m) = min {
                    v.push(Value::from(if *min_exclusive { *m } else { m - 1.0 }));
                }
                if let Some(m) = max {
                    v.push(Value::from(m + 1.0));
                }
                v
            }
            Kind::Choice { .. } => vec![Value::from("no-such-name")],
            Kind::Choices { .. } => vec![Value::from(vec!["no-such-name"])],
            Kind::Size => vec![Value::from("lots")],
            _ => vec![],
        };
        for value in past {
            let options: BakeOptions =
                serde_json::from_value(serde_json::json!({ setting.name: value.clone() })).unwrap();
            let error = options.validate().unwrap_err().to_string();
            assert!(
                error.starts_with(setting.name),
                "{}: {value} gave {error}",
                setting.name
            );
        }
    }
}
