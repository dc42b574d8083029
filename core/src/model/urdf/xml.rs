//! A light scan of the URDF's text for what urdf-rs does not tell: which joint or link an XML
//! fault lies in (an element given twice, a number that is none), and which joints have a
//! `<limit>` element at all.

/// A `<joint>` or `<link>` element directly under `<robot>`: its name and its children's tags.
pub(super) struct Element {
    /// `joint` or `link`.
    pub kind: String,
    /// Its `name` attribute (empty when it has none).
    pub name: String,
    /// The tags of its child elements, in order.
    pub children: Vec<String>,
}

/// The joint or link at fault for urdf-rs's error `message`, with what is wrong, when the text
/// shows it: a child element given twice, a joint without `<parent>` or `<child>`, or an
/// attribute that should hold numbers and does not (urdf-rs says only `invalid float literal`).
pub(super) fn fault(urdf: &str, message: &str) -> Option<(String, String)> {
    if message.contains("float") {
        return bad_number(urdf);
    }
    let elements = top_elements(urdf);
    if let Some(field) = quoted_after(message, "duplicate field `") {
        let count = |e: &Element| e.children.iter().filter(|c| *c == field).count();
        let e = elements.iter().find(|e| count(e) > 1)?;
        return Some((
            format!("{} '{}' <{field}>", e.kind, e.name),
            format!(
                "has {} <{field}> elements: a {} has at most one",
                count(e),
                e.kind
            ),
        ));
    }
    let field = quoted_after(message, "missing field `")?;
    if !matches!(field, "parent" | "child") {
        return None;
    }
    let e = elements
        .iter()
        .find(|e| e.kind == "joint" && !e.children.iter().any(|c| c == field))?;
    Some((
        format!("joint '{}'", e.name),
        format!("has no <{field}>: a joint names its {field} link"),
    ))
}

/// The attributes of the URDF element `tag` that hold a number or a list of numbers.
fn numeric_attributes(tag: &str) -> &'static [&'static str] {
    match tag {
        "origin" => &["xyz", "rpy"],
        "mass" => &["value"],
        "inertia" => &["ixx", "ixy", "ixz", "iyy", "iyz", "izz"],
        "axis" => &["xyz"],
        "limit" => &["lower", "upper", "effort", "velocity"],
        "dynamics" => &["damping", "friction"],
        "mimic" => &["multiplier", "offset"],
        "safety_controller" => &[
            "soft_lower_limit",
            "soft_upper_limit",
            "k_position",
            "k_velocity",
        ],
        "calibration" => &["rising", "falling"],
        "box" => &["size"],
        "cylinder" | "capsule" => &["radius", "length"],
        "sphere" => &["radius"],
        "mesh" => &["scale"],
        "color" => &["rgba"],
        _ => &[],
    }
}

/// The first attribute of `urdf` that should hold numbers and does not (e.g. `<mass
/// value="0.6kg"/>`): the element, in the joint or link it lies in, and what is wrong, with its
/// line.
fn bad_number(urdf: &str) -> Option<(String, String)> {
    let mut owner = "robot".to_owned();
    // The number of open elements, the root counting 1.
    let mut depth = 0usize;
    for (offset, tag) in tags(urdf) {
        if tag.starts_with('/') {
            depth = depth.saturating_sub(1);
            continue;
        }
        depth += 1;
        let name = tag_name(tag);
        if depth == 2 {
            owner = match (name, attribute(tag, "name")) {
                ("joint" | "link", Some(named)) => format!("{name} '{named}'"),
                _ => "robot".to_owned(),
            };
        }
        let numbers = |value: &str| {
            let mut parts = value.split_whitespace().peekable();
            parts.peek().is_some() && parts.all(|part| part.parse::<f64>().is_ok())
        };
        for key in numeric_attributes(name) {
            match attribute(tag, key) {
                Some(value) if !numbers(value) => {
                    let line = 1 + urdf[..offset].matches('\n').count();
                    let what = format!("line {line}: {key}=\"{value}\" is not a number");
                    return Some((format!("{owner} <{name}>"), what));
                }
                _ => {}
            }
        }
        if tag.ends_with('/') {
            depth -= 1;
        }
    }
    None
}

/// The element's name in the tag text `tag` (`mass` of `mass value="1"/`).
fn tag_name(tag: &str) -> &str {
    tag.split(|c: char| c.is_whitespace() || c == '/')
        .next()
        .unwrap_or_default()
}

/// The text between `prefix` and the next backtick in `message`.
fn quoted_after<'m>(message: &'m str, prefix: &str) -> Option<&'m str> {
    let rest = &message[message.find(prefix)? + prefix.len()..];
    Some(&rest[..rest.find('`')?])
}

/// The tags of `text` in order, each as its byte offset and the text between `<` and `>`.
/// Comments, CDATA sections, processing instructions and declarations are skipped; a tag cut
/// short ends them.
fn tags(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = text;
    std::iter::from_fn(move || loop {
        rest = &rest[rest.find('<')?..];
        let skip_to = if rest.starts_with("<!--") {
            rest.find("-->").map(|end| end + 3)
        } else if rest.starts_with("<![CDATA[") {
            rest.find("]]>").map(|end| end + 3)
        } else if rest.starts_with("<?") || rest.starts_with("<!") {
            rest.find('>').map(|end| end + 1)
        } else {
            None
        };
        if let Some(skip) = skip_to {
            rest = &rest[skip..];
            continue;
        }
        let end = tag_end(rest)?;
        let offset = text.len() - rest.len();
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        return Some((offset, tag));
    })
}

/// The line (from 1) of the first element of `urdf` nested deeper than `limit` (the root
/// element at depth 1), found in one pass over the text; None when none is.
pub(super) fn too_deep(urdf: &str, limit: usize) -> Option<usize> {
    let mut depth = 0usize;
    for (offset, tag) in tags(urdf) {
        if tag.starts_with('/') {
            depth = depth.saturating_sub(1);
            continue;
        }
        if depth + 1 > limit {
            return Some(1 + urdf[..offset].matches('\n').count());
        }
        if !tag.ends_with('/') {
            depth += 1;
        }
    }
    None
}

/// Every `<joint>` and `<link>` directly under the root element, in order (see [`tags`]).
pub(super) fn top_elements(urdf: &str) -> Vec<Element> {
    let mut elements = Vec::new();
    let mut current: Option<Element> = None;
    // The number of open elements, the root counting 1.
    let mut depth = 0usize;
    for (_, tag) in tags(urdf) {
        if !tag.starts_with('/') {
            depth += 1;
            let name = tag_name(tag);
            if depth == 2 && matches!(name, "joint" | "link") {
                current = Some(Element {
                    kind: name.to_owned(),
                    name: attribute(tag, "name").unwrap_or_default().to_owned(),
                    children: Vec::new(),
                });
            } else if let (3, Some(element)) = (depth, current.as_mut()) {
                element.children.push(name.to_owned());
            }
        }
        if tag.starts_with('/') || tag.ends_with('/') {
            depth = depth.saturating_sub(1);
            if depth == 1 {
                elements.extend(current.take());
            }
        }
    }
    elements
}

/// The index of the `>` that ends the tag starting `text`, outside quoted attribute values.
fn tag_end(text: &str) -> Option<usize> {
    let mut quote = None;
    for (i, c) in text.char_indices() {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '>') => return Some(i),
            _ => {}
        }
    }
    None
}

/// The value of attribute `key` in the tag text `tag` (without entity decoding).
fn attribute<'t>(tag: &'t str, key: &str) -> Option<&'t str> {
    let mut from = 0;
    while let Some(found) = tag[from..].find(key) {
        let at = from + found;
        from = at + key.len();
        if !tag[..at].ends_with(char::is_whitespace) {
            continue;
        }
        let Some(value) = tag[from..].trim_start().strip_prefix('=') else {
            continue;
        };
        let value = value.trim_start();
        let quote = value.chars().next().filter(|c| matches!(c, '"' | '\''))?;
        let value = &value[1..];
        return value.find(quote).map(|end| &value[..end]);
    }
    None
}
