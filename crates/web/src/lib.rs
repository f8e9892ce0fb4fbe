//! aograph in a web page.
pub fn probe() {}
