//! `[type_code, value]` parameters, typed.

use crate::Span;

/// A parameter value, typed by its code: 1 string, 2 int, 3 double, 4 bool.
/// A double written as an integer (`[3, 1]`) is stored as `Double(1.0)`.
#[derive(Debug, Clone, PartialEq)]
pub enum ParamValue {
    String(String),
    Int(i64),
    Double(f64),
    Bool(bool),
}

impl ParamValue {
    pub fn as_str(&self) -> Option<&str> {
        match self {
            ParamValue::String(s) => Some(s),
            _ => None,
        }
    }
    pub fn as_bool(&self) -> Option<bool> {
        match self {
            ParamValue::Bool(b) => Some(*b),
            _ => None,
        }
    }
    pub fn as_int(&self) -> Option<i64> {
        match self {
            ParamValue::Int(i) => Some(*i),
            _ => None,
        }
    }
    /// Numeric value of an int or double parameter.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Int(i) => Some(*i as f64),
            ParamValue::Double(d) => Some(*d),
            _ => None,
        }
    }
    pub fn type_name(&self) -> &'static str {
        match self {
            ParamValue::String(_) => "string",
            ParamValue::Int(_) => "int",
            ParamValue::Double(_) => "double",
            ParamValue::Bool(_) => "bool",
        }
    }
}

#[derive(Debug, Clone, PartialEq)]
pub struct Param {
    pub name: String,
    pub value: ParamValue,
    pub span: Span,
}

/// Parameters in document order; names are unique (a later duplicate replaced the earlier
/// one at parse time, with a warning).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Params(pub Vec<Param>);

impl Params {
    pub fn get(&self, name: &str) -> Option<&ParamValue> {
        self.0.iter().find(|p| p.name == name).map(|p| &p.value)
    }
    pub fn param(&self, name: &str) -> Option<&Param> {
        self.0.iter().find(|p| p.name == name)
    }
    pub fn str(&self, name: &str) -> Option<&str> {
        self.get(name).and_then(ParamValue::as_str)
    }
    pub fn bool(&self, name: &str) -> Option<bool> {
        self.get(name).and_then(ParamValue::as_bool)
    }
    pub fn f64(&self, name: &str) -> Option<f64> {
        self.get(name).and_then(ParamValue::as_f64)
    }
    pub fn int(&self, name: &str) -> Option<i64> {
        self.get(name).and_then(ParamValue::as_int)
    }
    pub fn iter(&self) -> impl Iterator<Item = &Param> {
        self.0.iter()
    }
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
    /// Inserts or replaces, keeping the first position.
    pub fn insert(&mut self, p: Param) {
        match self.0.iter_mut().find(|q| q.name == p.name) {
            Some(q) => *q = p,
            None => self.0.push(p),
        }
    }
}
