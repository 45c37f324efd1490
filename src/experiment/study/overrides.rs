//! Setting values inside a merged experiment table by key path, e.g.
//! `structure.damping.modal_ratios` or `cases[*].dampers[*].clearance_mm`.
//!
//! A path is made of names separated by dots; a name may carry a selector in brackets: an
//! index (`[0]`), every element (`[*]`) or the element whose `id` is the text (`[triple]`).
//! A number set on an array of numbers sets every element (unless the path selects one); a
//! number replaces an export reference (`"@EXPERIMENT.KEY"`) too. A missing last name is
//! added to its table, so that the experiment's own validation names a misspelt key.

use crate::error::file::OverrideError;

/// One step of a key path.
#[derive(Debug, Clone, PartialEq, Eq)]
enum Selector {
    /// Every element of an array.
    All,
    /// The element at an index.
    Index(usize),
    /// The element (a table) whose `id` is this.
    Id(String),
}

#[derive(Debug, Clone, PartialEq, Eq)]
struct Segment {
    name: String,
    selector: Option<Selector>,
}

/// A parsed key path.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct KeyPath {
    text: String,
    segments: Vec<Segment>,
}

impl KeyPath {
    /// Parses `a.b[*].c`; the error says what is allowed.
    pub fn parse(text: &str) -> Result<KeyPath, OverrideError> {
        if text.is_empty() {
            return Err(OverrideError::Syntax);
        }
        let mut segments = Vec::new();
        for part in text.split('.') {
            let (name, selector) = match part.split_once('[') {
                None => (part, None),
                Some((name, rest)) => {
                    let Some(inner) = rest.strip_suffix(']') else { return Err(OverrideError::Syntax) };
                    let sel = if inner == "*" {
                        Selector::All
                    } else if let Ok(i) = inner.parse::<usize>() {
                        Selector::Index(i)
                    } else if super::super::fields::is_identifier(inner) {
                        Selector::Id(inner.to_string())
                    } else {
                        return Err(OverrideError::Syntax);
                    };
                    (name, Some(sel))
                }
            };
            if name.is_empty() || !name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                return Err(OverrideError::Syntax);
            }
            segments.push(Segment { name: name.to_string(), selector });
        }
        Ok(KeyPath { text: text.to_string(), segments })
    }

    /// The path as written.
    pub fn as_str(&self) -> &str {
        &self.text
    }

    /// The first name (`structure`, `excitation`, `cases`, ...).
    pub fn root(&self) -> &str {
        &self.segments[0].name
    }

    /// Sets `value` everywhere the path points in `table`; returns how many values were set
    /// (at least one), or why none could be.
    pub fn set(&self, table: &mut toml::Table, value: &toml::Value) -> Result<usize, OverrideError> {
        let n = set_in(table, &self.segments, value)?;
        if n == 0 {
            return Err(OverrideError::SelectsNothing);
        }
        Ok(n)
    }
}

impl KeyPath {
    /// The values the path points at in `table`, as [`KeyPath::set`] would set them: a list of
    /// numbers at the end of the path gives its elements. Empty when the path selects nothing.
    pub fn get<'a>(&self, table: &'a toml::Table) -> Vec<&'a toml::Value> {
        let mut out = Vec::new();
        get_in(table, &self.segments, &mut out);
        out
    }
}

fn get_in<'a>(table: &'a toml::Table, segments: &[Segment], out: &mut Vec<&'a toml::Value>) {
    let Some((seg, rest)) = segments.split_first() else { return };
    let Some(slot) = table.get(&seg.name) else { return };
    let targets: Vec<&toml::Value> = match (&seg.selector, slot) {
        (None, v) => vec![v],
        (Some(Selector::All), toml::Value::Array(items)) => items.iter().collect(),
        (Some(Selector::Index(i)), toml::Value::Array(items)) => items.get(*i).into_iter().collect(),
        (Some(Selector::Id(id)), toml::Value::Array(items)) => {
            items.iter().filter(|v| v.get("id").and_then(|x| x.as_str()) == Some(id)).take(1).collect()
        }
        (Some(_), _) => Vec::new(),
    };
    for t in targets {
        match (rest.is_empty(), t) {
            (true, toml::Value::Array(items)) => out.extend(items.iter()),
            (true, v) => out.push(v),
            (false, toml::Value::Table(inner)) => get_in(inner, rest, out),
            (false, _) => {}
        }
    }
}

fn set_in(table: &mut toml::Table, segments: &[Segment], value: &toml::Value) -> Result<usize, OverrideError> {
    let (seg, rest) = segments.split_first().ok_or(OverrideError::Syntax)?;
    let last = rest.is_empty();
    if last && seg.selector.is_none() {
        return Ok(match table.get_mut(&seg.name) {
            Some(slot) => assign(slot, value)?,
            None => {
                table.insert(seg.name.clone(), value.clone());
                1
            }
        });
    }
    let Some(slot) = table.get_mut(&seg.name) else {
        return Err(OverrideError::NoKey { name: seg.name.clone(), keys: table.keys().cloned().collect() });
    };
    let targets: Vec<&mut toml::Value> = match (&seg.selector, slot) {
        (None, v) => vec![v],
        (Some(sel), toml::Value::Array(items)) => select(&seg.name, sel, items)?,
        (Some(_), other) => return Err(OverrideError::NotAList { name: seg.name.clone(), found: other.type_str() }),
    };
    let mut n = 0;
    for t in targets {
        n += if last {
            assign(t, value)?
        } else {
            match t {
                toml::Value::Table(inner) => set_in(inner, rest, value)?,
                other => {
                    return Err(OverrideError::NotATable { name: seg.name.clone(), found: other.type_str() });
                }
            }
        };
    }
    Ok(n)
}

fn select<'a>(
    name: &str,
    sel: &Selector,
    items: &'a mut [toml::Value],
) -> Result<Vec<&'a mut toml::Value>, OverrideError> {
    let len = items.len();
    match sel {
        Selector::All => Ok(items.iter_mut().collect()),
        Selector::Index(i) => items.get_mut(*i).map(|v| vec![v]).ok_or_else(|| OverrideError::OutOfRange {
            name: name.to_string(),
            len,
            index: *i,
        }),
        Selector::Id(id) => {
            let ids: Vec<String> =
                items.iter().filter_map(|v| v.get("id").and_then(|x| x.as_str()).map(String::from)).collect();
            items
                .iter_mut()
                .find(|v| v.get("id").and_then(|x| x.as_str()) == Some(id))
                .map(|v| vec![v])
                .ok_or_else(|| OverrideError::NoId { name: name.to_string(), id: id.clone(), ids })
        }
    }
}

/// Replaces one value; a number set on a list of numbers sets each element.
fn assign(slot: &mut toml::Value, value: &toml::Value) -> Result<usize, OverrideError> {
    let number = matches!(value, toml::Value::Float(_) | toml::Value::Integer(_));
    match slot {
        toml::Value::Array(items) if number => {
            if items.is_empty() || !items.iter().all(is_number_like) {
                return Err(OverrideError::NotNumbers);
            }
            for item in items.iter_mut() {
                *item = converted(item, value);
            }
            Ok(items.len())
        }
        toml::Value::Table(_) if number => Err(OverrideError::TableNotNumber),
        other => {
            *other = converted(other, value);
            Ok(1)
        }
    }
}

fn is_number_like(v: &toml::Value) -> bool {
    match v {
        toml::Value::Float(_) | toml::Value::Integer(_) => true,
        toml::Value::String(s) => s.starts_with('@'),
        _ => false,
    }
}

/// `value`, as an integer where the value it replaces is one and the number is whole.
fn converted(old: &toml::Value, value: &toml::Value) -> toml::Value {
    match (old, value) {
        (toml::Value::Integer(_), toml::Value::Float(f)) if f.fract() == 0.0 && f.abs() < 9.0e15 => {
            toml::Value::Integer(*f as i64)
        }
        _ => value.clone(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::file::PATH_SYNTAX;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn sets_lists_selected_elements_and_exports() {
        let mut t = table(
            "[structure.damping]\nmodal_ratios = [0.01, 0.01, 0.01]\n[[cases]]\nid = \"one\"\ndampers = [{ mass = 2, clearance_mm = \"@scan.best\" }]\n[[cases]]\nid = \"three\"\ndampers = [{ mass = 1, clearance_mm = 0.3 }, { mass = 2, clearance_mm = 0.3 }]",
        );
        let p = KeyPath::parse("structure.damping.modal_ratios").unwrap();
        assert_eq!(p.set(&mut t, &toml::Value::Float(0.005)), Ok(3));
        assert_eq!(t["structure"]["damping"]["modal_ratios"][2].as_float(), Some(0.005));
        let all = KeyPath::parse("cases[*].dampers[*].clearance_mm").unwrap();
        assert_eq!(all.set(&mut t, &toml::Value::Float(0.25)), Ok(3));
        assert_eq!(t["cases"][0]["dampers"][0]["clearance_mm"].as_float(), Some(0.25));
        let one = KeyPath::parse("cases[three].dampers[1].clearance_mm").unwrap();
        assert_eq!(one.set(&mut t, &toml::Value::Float(0.4)), Ok(1));
        assert_eq!(t["cases"][1]["dampers"][1]["clearance_mm"].as_float(), Some(0.4));
        assert_eq!(t["cases"][1]["dampers"][0]["clearance_mm"].as_float(), Some(0.25));
        // An integer stays an integer when the number is whole.
        let mass = KeyPath::parse("cases[0].dampers[0].mass").unwrap();
        mass.set(&mut t, &toml::Value::Float(3.0)).unwrap();
        assert_eq!(t["cases"][0]["dampers"][0]["mass"].as_integer(), Some(3));
    }

    #[test]
    fn errors_say_what_exists() {
        let mut t = table("[excitation]\nforce_n = 2.6\n[[cases]]\nid = \"one\"\ndampers = []");
        let set = |path: &str, t: &mut toml::Table| {
            KeyPath::parse(path).unwrap().set(t, &toml::Value::Float(1.0)).unwrap_err().to_string()
        };
        let e = set("excitatio.force_n", &mut t);
        assert!(e.contains("no key \"excitatio\"") && e.contains("excitation"), "{e}");
        let e = set("cases[two].label", &mut t);
        assert!(e.contains("[\"one\"]"), "{e}");
        let e = set("cases[*].dampers[*].mass", &mut t);
        assert!(e.contains("no value"), "{e}");
        assert_eq!(
            KeyPath::parse("a..b").unwrap_err().to_string(),
            PATH_SYNTAX.to_string(),
            "the path's syntax, as the message said it"
        );
        assert!(KeyPath::parse("a..b").is_err());
        assert!(KeyPath::parse("a[").is_err());
        assert!(KeyPath::parse("a[b c]").is_err());
    }

    #[test]
    fn gets_what_set_would_set() {
        let t = table(
            "[structure.damping]\nmodal_ratios = [0.01, 0.02, 0.03]\n[excitation]\nforce_n = 2.6\n[[cases]]\nid = \"one\"\ndampers = [{ mass = 2, clearance_mm = \"@scan.best\" }]\n[[cases]]\nid = \"three\"\ndampers = [{ mass = 1, clearance_mm = 0.3 }, { mass = 2, clearance_mm = 0.4 }]",
        );
        let get =
            |path: &str| -> Vec<toml::Value> { KeyPath::parse(path).unwrap().get(&t).into_iter().cloned().collect() };
        let f = toml::Value::Float;
        assert_eq!(get("structure.damping.modal_ratios"), vec![f(0.01), f(0.02), f(0.03)]);
        assert_eq!(get("excitation.force_n"), vec![f(2.6)]);
        assert_eq!(
            get("cases[*].dampers[*].clearance_mm"),
            vec![toml::Value::String("@scan.best".into()), f(0.3), f(0.4)]
        );
        assert_eq!(get("cases[three].dampers[1].clearance_mm"), vec![f(0.4)]);
        assert!(get("cases[two].dampers[0].clearance_mm").is_empty());
        assert!(get("cases[5].label").is_empty());
        assert!(get("excitation.force_n.x").is_empty());
        assert!(get("nowhere").is_empty());
    }
}
