//! Random edits of saved JSON, for the readers' property tests: every leaf's path, and
//! seven kinds of edit of a leaf.
#![allow(dead_code)] // each test file uses part of it

use serde_json::Value;

/// The kinds of edit [`edit`] makes.
pub const EDITS: usize = 7;

/// Edit `op` of the leaf at `path`: a number scaled by (1 + 1e-9), (1 + 1e-3), moved by 0.3,
/// negated, zeroed or increased by one; a flag flipped; a string replaced; or the last entry
/// of the leaf's list removed.
pub fn edit(v: &mut Value, path: &[Step], op: usize) {
    if op == EDITS - 1 {
        let list = path
            .iter()
            .rposition(|s| matches!(s, Step::Index(_)))
            .and_then(|k| at(v, &path[..k]))
            .and_then(Value::as_array_mut);
        if let Some(list) = list {
            list.pop();
        }
        return;
    }
    let Some(leaf) = at(v, path) else { return };
    *leaf = match &*leaf {
        Value::Number(n) => {
            let x = n.as_f64().unwrap_or(0.0);
            let y = [
                x * (1.0 + 1e-9),
                x * (1.0 + 1e-3),
                x + 0.3,
                -x,
                0.0,
                x + 1.0,
            ][op];
            if n.is_u64() && y >= 0.0 && y.fract() == 0.0 {
                Value::from(y as u64)
            } else {
                serde_json::Number::from_f64(y).map_or(Value::Null, Value::Number)
            }
        }
        Value::Bool(b) => Value::Bool(!b),
        Value::String(_) => Value::String("X".into()),
        other => other.clone(),
    };
}

#[derive(Debug, Clone)]
pub enum Step {
    Key(String),
    Index(usize),
}

pub fn at<'v>(v: &'v mut Value, path: &[Step]) -> Option<&'v mut Value> {
    path.iter().try_fold(v, |v, s| match s {
        Step::Key(k) => v.get_mut(k),
        Step::Index(i) => v.get_mut(*i),
    })
}

pub fn leaf_paths(v: &Value) -> Vec<Vec<Step>> {
    let mut out = Vec::new();
    let mut stack = vec![(v, Vec::new())];
    while let Some((v, path)) = stack.pop() {
        match v {
            Value::Object(m) => {
                for (k, x) in m {
                    let mut p = path.clone();
                    p.push(Step::Key(k.clone()));
                    stack.push((x, p));
                }
            }
            Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    let mut p = path.clone();
                    p.push(Step::Index(i));
                    stack.push((x, p));
                }
            }
            _ => out.push(path),
        }
    }
    out
}
