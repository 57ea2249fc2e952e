//! The two pest grammars (`grammar/rules.pest`, `grammar/map.pest`) and the human names of their
//! rules, used in "expected …" diagnostics. Nothing outside `syntax` sees these types except the
//! grammar tests, through `syntax::pest_parsers`.

pub use self::map::{MapGrammar, Rule as MapRule};
pub use self::rules::{Rule as RulesRule, RulesGrammar};

mod rules {
    #![allow(missing_docs)]
    /// The rule-file grammar.
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/rules.pest"]
    pub struct RulesGrammar;
}

mod map {
    #![allow(missing_docs)]
    /// The map-file grammar.
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/map.pest"]
    pub struct MapGrammar;
}

/// What a rule-file grammar rule is called in an "expected …" message.
pub fn rules_label(r: RulesRule) -> &'static str {
    use RulesRule as R;
    match r {
        R::ident | R::keyword => "a name",
        R::place_name | R::place_ref => "a place reference like `A_i`",
        R::number => "a number",
        R::kw_for => "`for`",
        R::kw_all => "`all`",
        R::kw_in => "`in`",
        R::kw_logic => "`logic`",
        R::kw_tracker => "`tracker`",
        R::kw_grid => "`grid`",
        R::kw_domain => "`domain`",
        R::kw_similarity => "`similarity`",
        R::kw_percept => "`percept`",
        R::kw_predicate => "`predicate`",
        R::kw_region => "`region`",
        R::kw_kind => "`kind`",
        R::kw_group => "`group`",
        R::region_decl => "a region declaration",
        R::region_set => "a set of places `{…}`",
        R::region_kind => "`kind name`",
        R::group_block => "a group `group name { … }`",
        R::query => "a query",
        R::turnstile => "`|-`",
        R::arrow => "`->`",
        R::file | R::item_entry | R::only_trivia | R::EOI => "end of input",
        R::logic_block => "a logic block",
        R::tracker_block => "a tracker block",
        R::grid_settings => "a grid block `grid { … }`",
        R::setting => "a setting `key = value;`",
        R::domain_decl => "a domain declaration",
        R::similarity_decl => "a similarity declaration",
        R::field => "a field `name: number`",
        R::percept_decl => "a percept declaration",
        R::predicate_decl => "a predicate declaration",
        R::roles => "an argument role list",
        R::rule => "a rule `|- body -> head;`",
        R::sequent => "a sequent `body -> head`",
        R::body => "a formula",
        R::literal => "a head atom",
        R::schema => "`for all …`",
        R::schema_vars => "schema variables",
        R::schema_source => "a domain or a set of tuples",
        R::tuple_set => "a set `{…}`",
        R::value_tuple => "a tuple of constants",
        R::formula | R::disj | R::conj | R::times | R::unary => "a formula",
        R::group => "`(`",
        R::or_op => "`(+)`",
        R::not_op => "`!`",
        R::atom => "an atom",
        R::arglist => "an argument list",
        R::place_key => "a key `(Name)`",
        R::tuple => "a tuple `<…>`",
        _ => "whitespace",
    }
}

/// What a map-file grammar rule is called in an "expected …" message.
pub fn map_label(r: MapRule) -> &'static str {
    use MapRule as R;
    match r {
        R::ident | R::keyword => "a name",
        R::number => "a number",
        R::integer => "an integer",
        R::string | R::string_text => "a string",
        R::kw_map => "`map`",
        R::kw_room => "`room`",
        R::kw_beacon => "`beacon`",
        R::kw_landmark => "`landmark`",
        R::kw_place => "`place`",
        R::kw_path => "`path`",
        R::kw_at => "`at`",
        R::kw_in => "`in`",
        R::kw_id => "`id`",
        R::kw_extent => "`extent`",
        R::kw_radius => "`radius`",
        R::kw_box => "`box`",
        R::kw_wall => "`wall`",
        R::kw_corner => "`corner`",
        R::kw_param => "`param`",
        R::kw_length => "`length`",
        R::kw_heading => "`heading`",
        R::kw_axis => "`axis`",
        R::kw_start => "`start`",
        R::kw_kinds => "`kinds`",
        R::kw_rotated => "`rotated`",
        R::kw_polygon => "`polygon`",
        R::kw_open => "`open`",
        R::kw_door => "`door`",
        R::axis_decl => "`axis degrees;`",
        R::start_decl => "`start (x, y);`",
        R::kinds_decl => "`kinds {kind, …};`",
        R::rotation => "`rotated degrees`",
        R::polygon => "`polygon ((x, y), …, (x, y))`",
        R::open => "`open Dir;`",
        R::door => "`door Dir;`",
        R::edge => "`--`",
        R::file | R::item_entry | R::only_trivia | R::EOI => "end of input",
        R::map_name => "`map name;`",
        R::room_decl => "a room declaration",
        R::landmark_decl => "a beacon or landmark declaration",
        R::point => "a point `(x, y)`",
        R::place_decl => "a place declaration",
        R::pose => "a pose `(x, y[, θ])`",
        R::extent => "an extent",
        R::radius => "`radius r`",
        R::box_extent => "`box (x0, y0, x1, y1)`",
        R::place_body => "`{` or `;`",
        R::wall => "`wall Dir;`",
        R::corner => "`corner D1 D2;`",
        R::param => "`param name = value;`",
        R::path_decl => "a path declaration",
        _ => "whitespace",
    }
}
